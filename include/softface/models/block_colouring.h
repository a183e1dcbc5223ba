#ifndef softface_block_colouring_h
#define softface_block_colouring_h

#include <cstddef>
#include <functional>
#include <vector>

namespace softface
{
  /**
   * The points of a point mesh cut into blocks of consecutive indices, and
   * the blocks coloured so that no point of a block is a neighbour of a
   * point in another block of the same colour. A Gauss-Seidel
   * sweep then visits the colours in turn and the blocks of one colour on
   * any number of threads at once, each block in index order: an update
   * writes its own point and reads its neighbours, so no two concurrent
   * blocks touch the same value, and the sweep is the same on one thread as
   * on many. With points in locality order (Mesh::order_for_locality) a
   * block is a compact piece of the mesh, and the colours are few.
   */
  struct BlockColouring
  {
    /**
     * Blocks of 256 points (independent of the number of threads and MPI
     * ranks, so that the order of the updates is too; and as many blocks as
     * the mesh has 256 points, so that many ranks each get blocks of every
     * colour: an earlier rule, n / 256 points per block, made 256 blocks of
     * any large mesh), coloured greedily in block order. @p row_start and
     * @p neighbour: the point mesh's symmetric adjacency in compressed rows.
     */
    BlockColouring(unsigned int                     n_points,
                   const std::vector<unsigned int> &row_start,
                   const std::vector<unsigned int> &neighbour);

    /// A single block of every point (one colour): the plain index order.
    explicit BlockColouring(unsigned int n_points);

    unsigned int
    n_blocks() const
    {
      return block_start.size() - 1;
    }

    /**
     * One sweep over @p points (ascending): @p update(b, begin, end) for
     * every block b, with points[begin..end) the ones in b; the blocks of a
     * colour on the threads at once, the colours in turn, and
     * @p after_colour(c, n), if given, once the blocks of colour c are done,
     * with n the points they updated (on several MPI ranks: the exchange of
     * PointExchange, and ColourUpdates).
     */
    void
    sweep(
      const std::vector<unsigned int>                                   &points,
      const std::function<void(unsigned int, std::size_t, std::size_t)> &update,
      const std::function<void(unsigned int, std::size_t)> &after_colour = {})
      const;

    /// Block b holds the points block_start[b] .. block_start[b+1]-1.
    std::vector<unsigned int> block_start;
    /// The blocks of each colour, ascending.
    std::vector<std::vector<unsigned int>> colours;
  };
} // namespace softface

#endif

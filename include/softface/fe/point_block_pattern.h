#ifndef softface_fe_point_block_pattern_h
#define softface_fe_point_block_pattern_h

#include <deal.II/lac/sparsity_pattern.h>

#include <array>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The sparsity of the shared P1 layout when its DoFs are point blocks
   * (3p, 3p+1, 3p+2): each DoF couples with every component of its own
   * point and of every point it shares a tetrahedron with. That is the
   * pattern DoFTools::make_sparsity_pattern() makes, here made from the
   * points' neighbour lists in one pass, with each row's length known
   * (deal.II inserts every cell's 144 entries into sorted rows, and on a
   * gmsh mesh its insertions take twice as long per cell as on the
   * generated cube, whose rows come nearly in order); and the place of any
   * entry in the value array of a SparseMatrix on it, found without
   * searching the row (a merge along the row mispredicts its branches on
   * an irregular mesh).
   *
   * Issue 16 (cell order): the same work per cell on any mesh.
   */
  class PointBlockPattern
  {
  public:
    /**
     * @p row_start and @p neighbour: the neighbours of point p, ascending,
     * are neighbour[row_start[p] .. row_start[p + 1]) (Models::PointMesh).
     * Both are referred to, not copied.
     */
    PointBlockPattern(const std::vector<unsigned int> &row_start,
                      const std::vector<unsigned int> &neighbour);
    PointBlockPattern(std::vector<unsigned int> &&,
                      std::vector<unsigned int> &&) = delete;

    /// Entries of the pattern (9 per pair of neighbours and per point).
    std::size_t
    n_entries() const;

    /// The pattern (3 x the points rows, square, compressed).
    void
    make_sparsity(SparsityPattern &sparsity) const;

    /**
     * Where the entries coupling the points @p p of a tetrahedron live in
     * the value array of a SparseMatrix on make_sparsity()'s pattern: entry
     * (3 p[a] + i, 3 p[b] + j) at @p positions[12 (3a + i) + 3b + j].
     */
    void
    cell_positions(const std::array<unsigned int, 4> &p,
                   unsigned int                      *positions) const;

  private:
    const std::vector<unsigned int> &row_start;
    const std::vector<unsigned int> &neighbour;

    /// The points of p's row (its neighbours and p) before point q.
    unsigned int
    blocks_before(const unsigned int p, const unsigned int q) const;
  };
} // namespace softface

#endif

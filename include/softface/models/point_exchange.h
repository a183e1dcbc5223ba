#ifndef softface_models_point_exchange_h
#define softface_models_point_exchange_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/partitioner.h>

#include <softface/core/point_mesh.h>
#include <softface/models/block_colouring.h>

#include <memory>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The points of a point-mesh model (mass tensor, mass spring) on several
   * MPI ranks. A rank updates the points of a range of the
   * model's blocks (BlockColouring): consecutive blocks, so a compact piece
   * of the mesh in locality order, balanced by their free points or by
   * another measure of their work (the mass spring model shares its blocks
   * again after each load step by that step's updates). The other
   * points it reads are ghosts, which it does not write.
   *
   * A sweep on the ranks is the serial sweep, update for update: the colours
   * in turn, each rank over its blocks of the colour, and after each colour
   * exchange() sends the values of that colour's points to the ranks that
   * read them. A serial sweep visits the same blocks in the same order, and
   * no two blocks of a colour are neighbours, so every update reads the
   * values it reads in serial, and the ranks' answers, sweeps and stop
   * decisions are the serial ones. (An earlier design swept the ranks'
   * interior points first and their borders last: another order, which
   * over-relaxation converged through more slowly, 29 % more updates on a
   * 2M-tetrahedron cube.) Ownership therefore follows the blocks rather
   * than the FEM models' DistributedLayout.
   *
   * Values live in the serial point numbering on every rank (three doubles
   * per point), so a sweep reads its neighbours as in serial.
   */
  class PointExchange
  {
  public:
    /**
     * The ranks' ranges of @p colouring's blocks, and for each colour who
     * reads which of the colour's points. The ranges balance each block's
     * free points plus its @p block_work (one figure per block, the same on
     * every rank; none by default). Collective.
     */
    PointExchange(const BlockColouring      &colouring,
                  const PointMesh           &mesh,
                  const MPI_Comm             communicator,
                  const std::vector<double> &block_work = {});

    /// The first block of each of @p n_ranks ranks (and, last, the number
    /// of blocks) when the ranges balance @p block_work as the constructor
    /// does.
    static std::vector<unsigned int>
    block_ranges(const BlockColouring      &colouring,
                 const PointMesh           &mesh,
                 const unsigned int         n_ranks,
                 const std::vector<double> &block_work = {});

    /// block_ranges() of this exchange.
    const std::vector<unsigned int> &
    ranges() const
    {
      return first_block;
    }

    const MPI_Comm communicator;

    /// Is @p point updated on this rank?
    bool
    owns(const unsigned int point) const
    {
      return point >= first_point && point < end_point;
    }

    /// The first point this rank owns (it owns n_owned_points() from it
    /// on).
    unsigned int
    first_owned_point() const
    {
      return first_point;
    }

    /// Points owned by this rank and held as ghosts, for reports.
    unsigned int
    n_owned_points() const
    {
      return end_point - first_point;
    }
    unsigned int
    n_ghost_points() const
    {
      return n_ghosts;
    }

    /**
     * After the blocks of colour @p colour: send this rank's values of that
     * colour's points to the ranks that read them, and take in theirs.
     * @p values holds 3 doubles per point in the serial numbering. Ghost
     * points that moved by more than @p moved_threshold (Euclidean, compared
     * as a sweep compares its steps) are appended to @p moved. Collective.
     */
    void
    exchange(const unsigned int         colour,
             double *const              values,
             const double               moved_threshold,
             std::vector<unsigned int> &moved) const;

    /// The same, with a ghost point in @p moved if its value changed at all
    /// (the mass spring model wakes a moved point's neighbours). Collective.
    void
    exchange(const unsigned int         colour,
             double *const              values,
             std::vector<unsigned int> &moved) const;

    /// exchange() for every colour (after a Jacobi sweep). Collective.
    void
    exchange_all(double *const              values,
                 const double               moved_threshold,
                 std::vector<unsigned int> &moved) const;

    /// Every point's value from its owner, on every rank. Collective.
    void
    gather(double *const values) const;

  private:
    /// exchange(), a ghost moved if its step exceeds @p moved_threshold
    /// (or, if @p any_change, if any component changed).
    void
    exchange(const unsigned int         colour,
             double *const              values,
             const double               moved_threshold,
             const bool                 any_change,
             std::vector<unsigned int> &moved) const;

    unsigned int              n_points = 0;
    std::vector<unsigned int> first_block;
    unsigned int              first_point = 0, end_point = 0;
    unsigned int              n_ghosts = 0;
    /// Every rank's values: where they begin and how many (gather()).
    std::vector<int> value_offsets, value_counts;

    /// Who reads which points of one colour: the ghost DoFs (3 per point,
    /// ascending) of this rank in the colour's blocks of other ranks.
    struct ColourExchange
    {
      std::shared_ptr<const Utilities::MPI::Partitioner> partitioner;
      std::vector<unsigned int>                          ghost_points;
      mutable std::vector<double> ghost_values, send_buffer;
    };
    std::vector<ColourExchange> colours;
  };

  /// The points a model updates on this rank: @p mesh's free points, with
  /// an @p exchange (several ranks) those of them this rank owns.
  std::vector<char>
  points_to_update(const PointMesh &mesh, const PointExchange *exchange);

  /// @p local summed, or its largest value, over the ranks of @p exchange;
  /// @p local itself without one (one rank). Collective.
  unsigned long long
  sum_over_ranks(const PointExchange *exchange, const unsigned long long local);
  double
  max_over_ranks(const PointExchange *exchange, const double local);

  /**
   * A rank's point updates colour by colour, sweep by sweep, for what the
   * ranks can gain in their sweeps: each colour waits for the rank with the
   * most updates in it, so the serial updates over the sum of those largest
   * counts bound the gain, however evenly the total is shared.
   */
  class ColourUpdates
  {
  public:
    /// This rank's updates in the colour just swept (or in the sweep, where
    /// no exchange separates its colours).
    void
    record(const std::size_t updates)
    {
      counts.push_back(static_cast<unsigned int>(updates));
    }

    /// Over everything recorded, the sum of the largest count on any rank.
    /// Collective; every rank must have recorded as often.
    unsigned long long
    slowest_sum(const MPI_Comm communicator) const;

  private:
    std::vector<unsigned int> counts;
  };
} // namespace softface

#endif

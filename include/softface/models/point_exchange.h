#ifndef softface_models_point_exchange_h
#define softface_models_point_exchange_h

#include <deal.II/base/mpi.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <softface/core/distributed_layout.h>
#include <softface/models/point_mesh.h>

#include <array>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The points of a point-mesh model (mass tensor, mass spring) on the ranks
   * of a DistributedLayout (issue 20). A rank updates the points whose DoFs
   * it owns in the layout, each point on exactly one rank; the other points
   * it holds are ghosts, which it reads and does not write. exchange() sends
   * every owned value to the ranks that hold it as a ghost (deal.II's
   * LinearAlgebra::distributed::Vector on the layout's owned and relevant
   * DoFs).
   *
   * A sweep stays a Gauss-Seidel sweep over all points, in an order of its
   * own: first every rank's interior points (no neighbour on another rank)
   * at once, then the border points colour by colour, the ranks coloured so
   * that no two neighbouring ranks share a colour, with an exchange after
   * each colour. Then every update reads its neighbours' latest values, as
   * in serial, and over-relaxation converges as it does in serial; a sweep
   * that let the ranks' borders lag a sweep behind (Jacobi between ranks)
   * diverged with the mass tensor model's factor 1.8.
   *
   * Values live in the serial point numbering on every rank (three doubles
   * per point, as the scene's DoFs), so a sweep reads its neighbours as in
   * serial.
   */
  class PointExchange
  {
  public:
    /**
     * The layout's owned DoFs decide who owns each of @p mesh's points; a
     * point is on the border if a free neighbour is another rank's (join
     * points never move). Collective.
     */
    PointExchange(const DistributedLayout &layout,
                  const Models::PointMesh &mesh);

    const MPI_Comm communicator;

    /// Is @p point updated on this rank?
    bool
    owns(const unsigned int point) const
    {
      return owned[point] != 0;
    }

    /// @p points (ascending, owned) split into those without and with a
    /// free neighbour on another rank, in the same order.
    void
    split(const std::vector<unsigned int> &points,
          std::vector<unsigned int>       &interior,
          std::vector<unsigned int>       &border) const;

    /// The colour of this rank's border points, and how many colours.
    unsigned int
    colour() const
    {
      return rank_colour;
    }
    unsigned int
    n_colours() const
    {
      return n_rank_colours;
    }

    /// Points owned by this rank and held as ghosts, for reports.
    unsigned int
    n_owned_points() const;
    unsigned int
    n_ghost_points() const;

    /**
     * Send this rank's owned values to the ranks that read them and take in
     * the ghost values. @p values holds 3 doubles per point in the serial
     * numbering. Ghost points whose value changed by more than
     * @p moved_threshold (Euclidean) are appended to @p moved. Collective.
     */
    void
    exchange(double *const              values,
             const double               moved_threshold,
             std::vector<unsigned int> &moved) const;

    /// Every point's value from its owner, on every rank. Collective.
    void
    gather(double *const values) const;

  private:
    unsigned int n_points;
    /// Per point: 0 not owned, 1 owned interior, 2 owned border.
    std::vector<char> owned;
    /// Owned DoFs: the buffer's local index and the serial DoF.
    std::vector<std::array<unsigned int, 2>> owned_dofs;
    /// Those that other ranks read (the ones exchange() sends).
    std::vector<std::array<unsigned int, 2>> exported_dofs;
    /// Ghost points, and the buffer's local index of each component.
    std::vector<unsigned int>                          ghost_points;
    std::vector<std::array<unsigned int, 3>>           ghost_local;
    unsigned int                                       rank_colour    = 0;
    unsigned int                                       n_rank_colours = 1;
    mutable LinearAlgebra::distributed::Vector<double> buffer;
  };

  /// The points a model updates on this rank: @p mesh's free points, with
  /// an @p exchange (several ranks) those of them this rank owns.
  std::vector<char>
  points_to_update(const Models::PointMesh &mesh,
                   const PointExchange     *exchange);

  /// @p local summed, or its largest value, over the ranks of @p exchange;
  /// @p local itself without one (one rank). Collective.
  unsigned long long
  sum_over_ranks(const PointExchange *exchange, const unsigned long long local);
  double
  max_over_ranks(const PointExchange *exchange, const double local);
} // namespace softface

#endif

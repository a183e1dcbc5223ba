// The sweeps of the point models (mass tensor, mass spring): what happens
// around their local updates, once for both. See models/point_sweeps.h.

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>

#include <softface/models/point_sweeps.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace softface
{
  PointSweeps::PointSweeps(const PointMesh      &mesh,
                           const BlockColouring &colouring,
                           const PointExchange  *exchange,
                           const Settings       &settings,
                           std::ostream         *progress)
      : row_start(mesh.row_start)
      , neighbour(mesh.neighbour)
      , mesh(mesh)
      , colouring(colouring)
      , exchange(nullptr)
      , settings(settings)
      , progress(progress)
      , active(mesh.n_points())
      , block_tally(colouring.n_blocks())
      , block_queued(colouring.n_blocks())
      , updates_in_block(colouring.n_blocks(), 0.)
  {
    Assert(colouring.block_start.back() == mesh.n_points(), ExcInternalError());
    use_exchange(exchange);
  }

  void
  PointSweeps::use_exchange(const PointExchange *new_exchange)
  {
    exchange = new_exchange;
    mine     = points_to_update(mesh, exchange);
    every_point.clear();
    for (unsigned int j = 0; j < mine.size(); ++j)
      if (mine[j])
        every_point.push_back(j);
  }

  SweepTally
  PointSweeps::fold_blocks()
  {
    SweepTally sweep_tally;
    for (unsigned int b = 0; b < block_tally.size(); ++b)
      {
        const SweepTally &tally = block_tally[b];
        if (!(tally.failure == 0.)) // NaN too
          sweep_tally.failure = std::isnan(tally.failure) ?
                                  std::numeric_limits<double>::infinity() :
                                  std::max(sweep_tally.failure, tally.failure);
        sweep_tally.all_stopped &= tally.all_stopped;
        sweep_tally.largest_step =
          std::max(sweep_tally.largest_step, tally.largest_step);
        sweep_tally.held_back += tally.held_back;
        active.add(block_queued[b]);
      }
    held_back += sweep_tally.held_back;
    return sweep_tally;
  }

  void
  PointSweeps::exchange_colour(const unsigned int colour,
                               const std::size_t  n_updated,
                               const double       threshold)
  {
    // On several ranks each colour's values travel before the next colour
    // (PointExchange): the serial sweep. A ghost that moved changed the
    // force on its neighbours here, as a neighbour's step does in serial.
    colour_updates.record(n_updated);
    moved_ghosts.clear();
    double *const values = settings.values;
    if (colour == numbers::invalid_unsigned_int)
      exchange->exchange_all(values, threshold, moved_ghosts);
    else if (settings.wake_on_any_change)
      exchange->exchange(colour, values, moved_ghosts);
    else
      exchange->exchange(colour, values, threshold, moved_ghosts);
    if (settings.active_set)
      for (const unsigned int g : moved_ghosts)
        for (unsigned int i = row_start[g]; i < row_start[g + 1]; ++i)
          if (mine[neighbour[i]])
            active.queue(neighbour[i]);
  }

  void
  PointSweeps::reduce(SweepTally &tally, bool &more) const
  {
    if (exchange == nullptr)
      return;
    // One reduction for every global decision of the sweep.
    std::array<double, 4> local = {{tally.largest_step,
                                    double(!tally.all_stopped),
                                    double(more),
                                    tally.failure}};
    Utilities::MPI::max(ArrayView<const double>(local),
                        exchange->communicator,
                        ArrayView<double>(local));
    tally.largest_step = local[0];
    tally.all_stopped  = local[1] == 0.;
    more               = local[2] != 0.;
    tally.failure      = local[3];
  }

  void
  PointSweeps::report_progress(const std::size_t  n_points,
                               const std::string &note) const
  {
    const auto n_active = sum(n_points);
    if (progress != nullptr)
      *progress << "      sweep " + std::to_string(sweep_count) + note + ": " +
                     std::to_string(n_active) + " active points\n"
                << std::flush;
  }

  std::vector<std::pair<std::string, double>>
  PointSweeps::rank_figures() const
  {
    if (exchange == nullptr)
      return {};
    const MPI_Comm communicator = exchange->communicator;
    return {{"points per rank (largest)",
             Utilities::MPI::max(exchange->n_owned_points(), communicator)},
            {"ghost points per rank (largest)",
             Utilities::MPI::max(exchange->n_ghost_points(), communicator)},
            // A colour waits for the rank with the most updates in it: the
            // busiest rank's share bounds what the ranks gain.
            {"busiest rank's point updates",
             double(Utilities::MPI::max(point_updates, communicator))},
            {"slowest rank's point updates, colour by colour",
             double(colour_updates.slowest_sum(communicator))}};
  }
} // namespace softface

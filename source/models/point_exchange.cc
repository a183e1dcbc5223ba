// Point values of the mass tensor and mass spring models on several MPI
// ranks: who updates which point, and the ghost exchange after
// each colour of a sweep. See models/point_exchange.h.

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.templates.h>
#include <deal.II/base/partitioner.templates.h>

#include <softface/core/error.h>
#include <softface/models/point_exchange.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace softface
{
  std::vector<unsigned int>
  PointExchange::block_ranges(const BlockColouring      &colouring,
                              const PointMesh           &mesh,
                              const unsigned int         n_ranks,
                              const std::vector<double> &block_work)
  {
    const auto        &start    = colouring.block_start;
    const unsigned int n_blocks = colouring.n_blocks();
    AssertThrow(block_work.empty() || block_work.size() == n_blocks,
                ExcMessage("One figure of work per block."));
    // Consecutive blocks per rank, as much work each as can be: a block's
    // free points (join points are not updated) and its measured work.
    std::vector<double> work_before(n_blocks + 1, 0.);
    for (unsigned int b = 0; b < n_blocks; ++b)
      {
        double work = block_work.empty() ? 0. : block_work[b];
        for (unsigned int j = start[b]; j < start[b + 1]; ++j)
          work += mesh.is_free[j];
        work_before[b + 1] = work_before[b] + work;
      }
    // Rank r's blocks begin at the first block with at least r / n_ranks of
    // the work before it (one pass for all ranks).
    std::vector<unsigned int> first_block(n_ranks + 1, n_blocks);
    for (unsigned int r = 0, b = 0; r < n_ranks; ++r)
      {
        while (b < n_blocks &&
               work_before[b] * n_ranks < work_before[n_blocks] * r)
          ++b;
        first_block[r] = b;
      }
    return first_block;
  }

  PointExchange::PointExchange(const BlockColouring      &colouring,
                               const PointMesh           &mesh,
                               const MPI_Comm             communicator,
                               const std::vector<double> &block_work)
      : communicator(communicator)
      , n_points(mesh.n_points())
  {
    const auto        &row_start = mesh.row_start;
    const auto        &neighbour = mesh.neighbour;
    const auto        &is_free   = mesh.is_free;
    const auto        &start     = colouring.block_start;
    const unsigned int n_blocks  = colouring.n_blocks();
    AssertThrow(row_start.size() == n_points + 1 &&
                  is_free.size() == n_points && start.back() == n_points,
                ExcMessage("The point mesh does not match the colouring."));
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    const unsigned int rank    = Utilities::MPI::this_mpi_process(communicator);
    first_block = block_ranges(colouring, mesh, n_ranks, block_work);
    first_point = start[first_block[rank]];
    end_point   = start[first_block[rank + 1]];
    // Every rank's range, for gather().
    AssertThrow(3 * std::size_t(n_points) <=
                  std::size_t(std::numeric_limits<int>::max()),
                ExcMessage("Too many points for one MPI message."));
    for (unsigned int r = 0; r < n_ranks; ++r)
      {
        value_offsets.push_back(3 * start[first_block[r]]);
        value_counts.push_back(3 * start[first_block[r + 1]] -
                               value_offsets.back());
      }

    std::vector<unsigned int> colour_of_block(n_blocks);
    for (unsigned int c = 0; c < colouring.colours.size(); ++c)
      for (const unsigned int b : colouring.colours[c])
        colour_of_block[b] = c;

    // Ghosts: the free points of other ranks that this rank's free points
    // read (join points never move, every rank has their values).
    std::vector<char> read(n_points, 0);
    for (unsigned int j = first_point; j < end_point; ++j)
      if (is_free[j])
        for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
          {
            const unsigned int k = neighbour[i];
            if (!owns(k) && is_free[k])
              read[k] = 1;
          }
    colours.resize(colouring.colours.size());
    std::vector<IndexSet> ghost_dofs(colours.size(), IndexSet(3 * n_points));
    unsigned int          block = 0;
    for (unsigned int k = 0; k < n_points; ++k)
      {
        while (start[block + 1] <= k)
          ++block;
        if (!read[k])
          continue;
        const unsigned int c = colour_of_block[block];
        colours[c].ghost_points.push_back(k);
        ghost_dofs[c].add_range(3 * k, 3 * k + 3);
        ++n_ghosts;
      }
    IndexSet owned_dofs(3 * n_points);
    owned_dofs.add_range(3 * first_point, 3 * end_point);
    for (unsigned int c = 0; c < colours.size(); ++c)
      {
        ghost_dofs[c].compress();
        auto &x = colours[c];
        x.partitioner =
          std::make_shared<Utilities::MPI::Partitioner>(owned_dofs,
                                                        ghost_dofs[c],
                                                        communicator);
        x.ghost_values.resize(x.partitioner->n_ghost_indices());
        x.send_buffer.resize(x.partitioner->n_import_indices());
      }
  }

  void
  PointExchange::exchange(const unsigned int         colour,
                          double *const              values,
                          const double               moved_threshold,
                          std::vector<unsigned int> &moved) const
  {
    exchange(colour, values, moved_threshold, false, moved);
  }

  void
  PointExchange::exchange(const unsigned int         colour,
                          double *const              values,
                          std::vector<unsigned int> &moved) const
  {
    exchange(colour, values, 0., true, moved);
  }

  void
  PointExchange::exchange(const unsigned int         colour,
                          double *const              values,
                          const double               moved_threshold,
                          const bool                 any_change,
                          std::vector<unsigned int> &moved) const
  {
    const ColourExchange    &x = colours[colour];
    std::vector<MPI_Request> requests;
    x.partitioner->export_to_ghosted_array_start<double>(
      0,
      ArrayView<const double>(values + 3 * std::size_t(first_point),
                              3 * std::size_t(end_point - first_point)),
      make_array_view(x.send_buffer),
      make_array_view(x.ghost_values),
      requests);
    x.partitioner->export_to_ghosted_array_finish<double>(
      make_array_view(x.ghost_values), requests);
    for (unsigned int g = 0; g < x.ghost_points.size(); ++g)
      {
        double *const v       = values + 3 * std::size_t(x.ghost_points[g]);
        double        change  = 0.;
        bool          changed = false;
        for (unsigned int c = 0; c < 3; ++c)
          {
            const double received = x.ghost_values[3 * g + c];
            change += (received - v[c]) * (received - v[c]);
            changed |= received != v[c];
            v[c] = received;
          }
        // As the owner's sweep compares the step it took.
        if (any_change ? changed : std::sqrt(change) > moved_threshold)
          moved.push_back(x.ghost_points[g]);
      }
  }

  void
  PointExchange::exchange_all(double *const              values,
                              const double               moved_threshold,
                              std::vector<unsigned int> &moved) const
  {
    for (unsigned int c = 0; c < colours.size(); ++c)
      exchange(c, values, moved_threshold, moved);
  }

  std::vector<char>
  points_to_update(const PointMesh &mesh, const PointExchange *exchange)
  {
    std::vector<char> update(mesh.n_points());
    for (unsigned int j = 0; j < update.size(); ++j)
      update[j] = mesh.is_free[j] && (!exchange || exchange->owns(j));
    return update;
  }

  unsigned long long
  sum_over_ranks(const PointExchange *exchange, const unsigned long long local)
  {
    return exchange ? Utilities::MPI::sum(local, exchange->communicator) :
                      local;
  }

  double
  max_over_ranks(const PointExchange *exchange, const double local)
  {
    return exchange ? Utilities::MPI::max(local, exchange->communicator) :
                      local;
  }

  void
  PointExchange::gather(double *const values) const
  {
    // Each rank's range in place, as its owner holds it.
    const int ierr = MPI_Allgatherv(MPI_IN_PLACE,
                                    0,
                                    MPI_DATATYPE_NULL,
                                    values,
                                    value_counts.data(),
                                    value_offsets.data(),
                                    MPI_DOUBLE,
                                    communicator);
    AssertThrowMPI(ierr);
  }

  unsigned long long
  ColourUpdates::slowest_sum(const MPI_Comm communicator) const
  {
    const unsigned long long n = counts.size();
    AssertThrow(Utilities::MPI::max(n, communicator) ==
                  Utilities::MPI::min(n, communicator),
                ExcMessage("The ranks recorded different numbers of colours."));
    std::vector<unsigned int> largest(counts.size());
    Utilities::MPI::max(counts, communicator, largest);
    return std::accumulate(largest.begin(), largest.end(), 0ULL);
  }
} // namespace softface

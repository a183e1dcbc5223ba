// Point values of the mass tensor and mass spring models on several MPI
// ranks (issue 20): who updates which point, and the ghost exchange after
// each sweep. See models/point_exchange.h.

#include <deal.II/base/mpi.templates.h>

#include <softface/core/error.h>
#include <softface/models/point_exchange.h>

#include <algorithm>
#include <cmath>

namespace softface
{
  PointExchange::PointExchange(const DistributedLayout &layout,
                               const Models::PointMesh &mesh)
      : communicator(layout.communicator)
      , n_points(layout.scene.dof_handler.n_dofs() / 3)
  {
    AssertThrow(layout.scene.dof_handler.n_dofs() % 3 == 0,
                ExcMessage("A point exchange needs three DoFs per point."));
    IndexSet ghosts = layout.locally_relevant_dofs;
    ghosts.subtract_set(layout.locally_owned_dofs);
    buffer.reinit(layout.locally_owned_dofs, ghosts, communicator);
    const auto &partitioner = *buffer.get_partitioner();

    owned.assign(n_points, 0);
    owned_dofs.reserve(layout.locally_owned_dofs.n_elements());
    for (const auto dof : layout.locally_owned_dofs)
      {
        const auto serial = layout.serial_dof(dof);
        owned[serial / 3] = 1;
        owned_dofs.push_back(
          {{static_cast<unsigned int>(partitioner.global_to_local(dof)),
            static_cast<unsigned int>(serial)}});
      }
    // A ghost point's three components, by point.
    std::vector<unsigned int> slot(n_points, numbers::invalid_unsigned_int);
    for (const auto dof : ghosts)
      {
        const auto   serial = layout.serial_dof(dof);
        unsigned int point  = serial / 3;
        if (slot[point] == numbers::invalid_unsigned_int)
          {
            slot[point] = ghost_points.size();
            ghost_points.push_back(point);
            ghost_local.push_back({{0, 0, 0}});
          }
        ghost_local[slot[point]][serial % 3] = partitioner.global_to_local(dof);
      }
    // Only the owned values another rank reads travel: the partitioner's
    // import indices (local, the owned DoFs in order).
    std::vector<bool> exported(owned_dofs.size(), false);
    for (const auto &range : partitioner.import_indices())
      for (unsigned int l = range.first; l < range.second; ++l)
        exported[l] = true;
    for (const auto &entry : owned_dofs)
      if (exported[entry[0]])
        exported_dofs.push_back(entry);

    const auto &row_start = mesh.row_start;
    const auto &neighbour = mesh.neighbour;
    const auto &is_free   = mesh.is_free;
    AssertThrow(row_start.size() == n_points + 1 && is_free.size() == n_points,
                ExcMessage("The point mesh does not match the layout."));

    // Border points: owned, with a free neighbour that is not. Every
    // neighbour of an owned point must be here, owned or a ghost (the owner
    // of a vertex owns a cell around it), or a sweep would read stale values.
    for (unsigned int j = 0; j < n_points; ++j)
      if (owned[j])
        for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
          {
            const unsigned int k = neighbour[i];
            AssertThrow(owned[k] || slot[k] != numbers::invalid_unsigned_int,
                        ExcMessage("A neighbour of point " + std::to_string(j) +
                                   " is neither owned nor a ghost here."));
            if (!owned[k] && is_free[k])
              owned[j] = 2;
          }

    // The ranks whose points border this rank's, on every rank; colours
    // given greedily in rank order, the same on every rank.
    std::vector<unsigned int> adjacent;
    for (const auto &target : partitioner.ghost_targets())
      adjacent.push_back(target.first);
    for (const auto &target : partitioner.import_targets())
      adjacent.push_back(target.first);
    const auto all_adjacent =
      Utilities::MPI::all_gather(communicator, adjacent);
    const unsigned int                     n_ranks = all_adjacent.size();
    std::vector<std::vector<unsigned int>> graph(n_ranks);
    for (unsigned int r = 0; r < n_ranks; ++r)
      for (const unsigned int s : all_adjacent[r])
        if (s != r)
          {
            graph[r].push_back(s);
            graph[s].push_back(r);
          }
    std::vector<unsigned int> colour_of(n_ranks, 0);
    for (unsigned int r = 0; r < n_ranks; ++r)
      {
        std::vector<bool> taken(n_ranks + 1, false);
        for (const unsigned int s : graph[r])
          if (s < r)
            taken[colour_of[s]] = true;
        while (taken[colour_of[r]])
          ++colour_of[r];
        n_rank_colours = std::max(n_rank_colours, colour_of[r] + 1);
      }
    rank_colour = colour_of[Utilities::MPI::this_mpi_process(communicator)];
  }

  void
  PointExchange::split(const std::vector<unsigned int> &points,
                       std::vector<unsigned int>       &interior,
                       std::vector<unsigned int>       &border) const
  {
    interior.clear();
    border.clear();
    for (const unsigned int j : points)
      (owned[j] == 2 ? border : interior).push_back(j);
  }

  unsigned int
  PointExchange::n_owned_points() const
  {
    return owned_dofs.size() / 3;
  }

  unsigned int
  PointExchange::n_ghost_points() const
  {
    return ghost_points.size();
  }

  void
  PointExchange::exchange(double *const              values,
                          const double               moved_threshold,
                          std::vector<unsigned int> &moved) const
  {
    for (const auto &[local, serial] : exported_dofs)
      buffer.local_element(local) = values[serial];
    buffer.update_ghost_values();
    const double threshold_squared = moved_threshold * moved_threshold;
    for (unsigned int g = 0; g < ghost_points.size(); ++g)
      {
        double *const v      = values + 3 * ghost_points[g];
        double        change = 0.;
        for (unsigned int c = 0; c < 3; ++c)
          {
            const double received = buffer.local_element(ghost_local[g][c]);
            change += (received - v[c]) * (received - v[c]);
            v[c] = received;
          }
        if (change > threshold_squared)
          moved.push_back(ghost_points[g]);
      }
  }

  std::vector<char>
  points_to_update(const Models::PointMesh &mesh, const PointExchange *exchange)
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
    std::vector<double> mine(3 * static_cast<std::size_t>(n_points), 0.);
    for (const auto &entry : owned_dofs)
      mine[entry[1]] = values[entry[1]];
    Utilities::MPI::sum(mine, communicator, mine);
    std::copy(mine.begin(), mine.end(), values);
  }
} // namespace softface

// The scene's layout on several MPI ranks (issue 20, a first step): the
// serial mesh partitioned, a fully distributed triangulation and DoFHandler
// per rank, and the map from its DoFs to the scene's, through which the
// serial decisions (join points) and vectors reach the ranks and answers come
// back. See core/distributed_layout.h.

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/sparsity_tools.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>

#include <algorithm>
#include <array>
#include <cstdint>

namespace softface
{
  DistributedTriangulation::DistributedTriangulation(
    const MPI_Comm communicator,
    const bool     allow_table)
      : parallel::fullydistributed::Triangulation<3>(communicator)
      , allow_table(allow_table)
  {}

  void
  DistributedTriangulation::create_triangulation(
    const TriangulationDescription::Description<3, 3> &description)
  {
    // The lookup first: deal.II's create_triangulation() sorts through
    // coarse_cell_id_to_coarse_cell_index().
    index_of_id.clear();
    sorted_ids.clear();
    const auto &ids = description.coarse_cell_index_to_coarse_cell_id;
    if (ids.empty())
      // deal.II builds a rank without cells one artificial cell, whose id
      // is the invalid one.
      sorted_ids.emplace_back(numbers::invalid_coarse_cell_id, 0);
    else
      {
        const auto [smallest, largest] =
          std::minmax_element(ids.begin(), ids.end());
        const std::uint64_t range = std::uint64_t(*largest) - *smallest + 1;
        if (allow_table && *largest != numbers::invalid_coarse_cell_id &&
            range <= 4 * std::uint64_t(ids.size()) + 1024)
          {
            first_id = *smallest;
            index_of_id.assign(range, numbers::invalid_unsigned_int);
            for (unsigned int i = 0; i < ids.size(); ++i)
              index_of_id[ids[i] - first_id] = i;
          }
        else
          {
            sorted_ids.reserve(ids.size());
            for (unsigned int i = 0; i < ids.size(); ++i)
              sorted_ids.emplace_back(ids[i], i);
            std::sort(sorted_ids.begin(), sorted_ids.end());
          }
      }
    parallel::fullydistributed::Triangulation<3>::create_triangulation(
      description);
  }

  unsigned int
  DistributedTriangulation::coarse_cell_id_to_coarse_cell_index(
    const types::coarse_cell_id coarse_cell_id) const
  {
    if (!index_of_id.empty())
      {
        const types::coarse_cell_id k = coarse_cell_id - first_id;
        AssertThrow(coarse_cell_id >= first_id && k < index_of_id.size() &&
                      index_of_id[k] != numbers::invalid_unsigned_int,
                    ExcMessage("Coarse cell " + std::to_string(coarse_cell_id) +
                               " is not on this rank."));
        return index_of_id[k];
      }
    const auto found = std::lower_bound(sorted_ids.begin(),
                                        sorted_ids.end(),
                                        std::make_pair(coarse_cell_id, 0u));
    AssertThrow(found != sorted_ids.end() && found->first == coarse_cell_id,
                ExcMessage("Coarse cell " + std::to_string(coarse_cell_id) +
                           " is not on this rank."));
    return found->second;
  }

  bool
  DistributedTriangulation::has_index_table() const
  {
    return !index_of_id.empty();
  }

  DistributedLayout::Partitioner
  DistributedLayout::parse_partitioner(const std::string &name)
  {
    if (name == "cell order")
      return Partitioner::cell_order;
    if (name == "metis")
      return Partitioner::metis;
    throw Error("Unknown partitioner '" + name +
                "'; use 'cell order' or 'metis'.");
  }

  void
  DistributedLayout::declare_partitioner(ParameterHandler &prm)
  {
    prm.declare_entry("Partitioner",
                      "cell order",
                      Patterns::Selection("cell order|metis"),
                      "On several MPI ranks (mpirun), how the cells are "
                      "shared among them: 'cell order' (contiguous pieces "
                      "of the cells' order, a space-filling curve for a "
                      "read mesh) or 'metis' (METIS on the cells' face "
                      "graph: fewer faces between the ranks).");
  }

  SharedDistributedLayout::SharedDistributedLayout(
    const MPI_Comm                       communicator,
    const DistributedLayout::Partitioner partitioner)
      : communicator(communicator)
      , partitioner(partitioner)
  {}

  const DistributedLayout &
  SharedDistributedLayout::get(const Scene &scene)
  {
    // One layout per run: the models keep references to it.
    AssertThrow(!layout || &layout->scene == &scene,
                ExcMessage("A shared layout serves one scene."));
    if (!layout)
      layout =
        std::make_unique<DistributedLayout>(scene, communicator, partitioner);
    return *layout;
  }

  DistributedLayout::DistributedLayout(const Scene      &scene,
                                       const MPI_Comm    communicator,
                                       const Partitioner partitioner)
      : scene(scene)
      , communicator(communicator)
      , triangulation(communicator)
  {
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    // A coarse cell id is the serial cell's active index only on an
    // unrefined mesh (softface's meshes are).
    AssertThrow(scene.triangulation.n_levels() == 1,
                ExcMessage("A refined mesh cannot be distributed yet."));

    // A copy of the serial mesh whose subdomain ids name each cell's rank:
    // the scene's own mesh stays as the serial models use it.
    Triangulation<3> partitioned;
    partitioned.copy_triangulation(scene.triangulation);
    if (partitioner == Partitioner::metis && n_ranks > 1)
      {
        // METIS on rank 0 only, its owners sent to all: every rank must
        // build its description from the same partition.
        std::vector<unsigned int> owner(partitioned.n_active_cells());
        if (Utilities::MPI::this_mpi_process(communicator) == 0)
          {
            GridTools::partition_triangulation(
              n_ranks, partitioned, SparsityTools::Partitioner::metis);
            for (const auto &cell : partitioned.active_cell_iterators())
              owner[cell->active_cell_index()] = cell->subdomain_id();
          }
        owner = Utilities::MPI::broadcast(communicator, owner);
        for (const auto &cell : partitioned.active_cell_iterators())
          cell->set_subdomain_id(owner[cell->active_cell_index()]);
      }
    else
      {
        const std::uint64_t n_cells = partitioned.n_active_cells();
        for (const auto &cell : partitioned.active_cell_iterators())
          cell->set_subdomain_id(static_cast<types::subdomain_id>(
            std::uint64_t(cell->active_cell_index()) * n_ranks / n_cells));
      }
    triangulation.create_triangulation(
      TriangulationDescription::Utilities::
        create_description_from_triangulation(partitioned, communicator));

    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(scene.fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

    // A cell of this rank is the serial cell of its coarse cell id (the
    // description numbers coarse cells as the serial mesh does), with its
    // vertices in the same order: the DoFs of a vertex and component
    // correspond.
    serial_dof_of_relevant.assign(locally_relevant_dofs.n_elements(),
                                  numbers::invalid_dof_index);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          const DoFHandler<3>::active_cell_iterator serial(
            &scene.triangulation,
            0,
            cell->id().get_coarse_cell_id(),
            &scene.dof_handler);
          for (const unsigned int v : cell->vertex_indices())
            for (unsigned int c = 0; c < 3; ++c)
              serial_dof_of_relevant[locally_relevant_dofs.index_within_set(
                cell->vertex_dof_index(v, c))] = serial->vertex_dof_index(v, c);
        }
  }

  types::global_dof_index
  DistributedLayout::serial_dof(const types::global_dof_index dof) const
  {
    AssertThrow(locally_relevant_dofs.is_element(dof),
                ExcMessage("DoF " + std::to_string(dof) +
                           " is not locally relevant on this rank."));
    return serial_dof_of_relevant[locally_relevant_dofs.index_within_set(dof)];
  }

  Triangulation<3>::active_cell_iterator
  DistributedLayout::serial_cell(
    const DoFHandler<3>::active_cell_iterator &cell) const
  {
    return Triangulation<3>::active_cell_iterator(
      &scene.triangulation, 0, cell->id().get_coarse_cell_id());
  }

  void
  DistributedLayout::cells_at_owned_dofs(
    std::vector<DoFHandler<3>::active_cell_iterator> &cells,
    std::vector<types::global_dof_index>             &cell_dofs) const
  {
    cells.clear();
    cell_dofs.clear();
    std::array<types::global_dof_index, 12> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          bool at_owned_dof = false;
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              {
                dofs[3 * a + i] = cell->vertex_dof_index(a, i);
                at_owned_dof |= locally_owned_dofs.is_element(dofs[3 * a + i]);
              }
          if (!at_owned_dof)
            continue;
          cells.push_back(cell);
          cell_dofs.insert(cell_dofs.end(), dofs.begin(), dofs.end());
        }
  }

  bool
  DistributedLayout::is_join_dof(const types::global_dof_index dof) const
  {
    return scene.join_dofs()[serial_dof(dof)];
  }

  void
  DistributedLayout::scatter(const Vector<double>          &serial,
                             TrilinosWrappers::MPI::Vector &distributed) const
  {
    for (const auto dof : locally_owned_dofs)
      distributed[dof] = serial[serial_dof(dof)];
    distributed.compress(VectorOperation::insert);
  }

  Vector<double>
  DistributedLayout::gather(
    const TrilinosWrappers::MPI::Vector &distributed) const
  {
    // Each rank writes its owned entries into a zero serial vector; the sum
    // over the ranks is the whole vector, since every DoF has one owner.
    Vector<double> serial(scene.dof_handler.n_dofs());
    for (const auto dof : locally_owned_dofs)
      serial[serial_dof(dof)] = distributed[dof];
    Utilities::MPI::sum(serial, communicator, serial);
    return serial;
  }
} // namespace softface

// The scene's layout on several MPI ranks, run by
// ctest on 2 and 3 ranks (distributed_layout.mpirun=N.output). Against the
// serial scene it is built from, on the generated cube and on a read gmsh
// mesh, with both partitioners:
// - every serial DoF is owned by exactly one rank, and a rank's DoF sits at
//   the vertex of the serial DoF it maps to (its component too);
// - join points decided per owned vertex on the ranks are the serial ones,
//   at every locally relevant DoF, and give the serial counts per segment
//   (the cube's slabs on 3 ranks: the inner bone on the middle rank only, the
//   other two own none of its join points);
// - scatter and gather of a serial field give it back exactly, and a field
//   set on the ranks from their own support points gathers to the serial
//   field at the scene's support points;
// - the layout's triangulation (DistributedTriangulation, a table from
//   coarse cell id to index) holds the cells of deal.II's own fully
//   distributed triangulation built from the same description, in the same
//   order, with the same owners and vertices, and its lookup answers each
//   cell's index, with the table and with the binary search kept for
//   scattered ids, also on a rank without cells;
// - a vertex touching two segments is refused on every rank with one
//   message where the scene does not leave it free;
// - each rank's part, described from the mesh without a copy of it (by any
//   rank), equals deal.II's description of it, and the cells' ranks are
//   those of deal.II's partition (GridTools::partition_triangulation() with
//   METIS, the cell order's ranges);
// - each rank decides its cells' tissues and its owned vertices' nodal
//   body force by the effects' rules per material id, as the scene's
//   arrays have them (the loads to round-off);
// - in groups of ranks whose root describes and sends its members' parts,
//   the layout is the same, and its members read nothing of the scene's
//   mesh (their copy of the scene has none).

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_vector.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>

#include "effects.h"
#include "peer.h"
#include "scenes.h"
#include "tests.h"

#include <algorithm>
#include <cstdint>
#include <map>

using namespace softface_tests;

namespace
{
  /// A field that tells the DoFs apart: linear in the point, offset by the
  /// component.
  double
  field(const Point<3> &x, const unsigned int component)
  {
    return x[0] + 2. * x[1] + 3. * x[2] + 1000. * component;
  }

  /// @p description with the manifold ids of the lines and faces a
  /// tetrahedron does not have set alike: deal.II leaves them uninitialised
  /// (its arrays are a hexahedron's), so that equal descriptions would
  /// compare unequal.
  TriangulationDescription::Description<3, 3>
  tetrahedra_only(TriangulationDescription::Description<3, 3> description)
  {
    for (auto &level : description.cell_infos)
      for (auto &cell : level)
        {
          std::fill(cell.manifold_line_ids.begin() + 6,
                    cell.manifold_line_ids.end(),
                    numbers::flat_manifold_id);
          std::fill(cell.manifold_quad_ids.begin() + 4,
                    cell.manifold_quad_ids.end(),
                    numbers::flat_manifold_id);
        }
    return description;
  }

  /// Each of @p ours against deal.II's own fully distributed triangulation
  /// @p reference built from the same description: the same cells, owners
  /// and vertices in the same order, and the coarse cell lookup answering
  /// each cell's level-0 index. Collective.
  void
  check_against_dealii(
    const std::string                                   &indent,
    const parallel::fullydistributed::Triangulation<3>  &reference,
    const std::vector<const DistributedTriangulation *> &ours)
  {
    unsigned int differences = 0, wrong_lookups = 0;
    for (const DistributedTriangulation *tria : ours)
      {
        differences += tria->n_active_cells() != reference.n_active_cells();
        auto other = reference.begin_active();
        for (const auto &cell : tria->active_cell_iterators())
          {
            if (other == reference.end())
              break;
            for (const unsigned int v : cell->vertex_indices())
              differences += cell->vertex(v) != other->vertex(v);
            differences += cell->is_artificial() != other->is_artificial();
            // A rank without cells holds deal.II's dummy cell, which has no
            // id.
            if (!cell->is_artificial() && !other->is_artificial())
              {
                differences += cell->id() != other->id() ||
                               cell->subdomain_id() != other->subdomain_id();
                const auto id = cell->id().get_coarse_cell_id();
                // A coarse cell's index is its index on level 0.
                wrong_lookups +=
                  tria->coarse_cell_id_to_coarse_cell_index(id) !=
                  static_cast<unsigned int>(other->index());
              }
            ++other;
          }
      }
    const MPI_Comm comm = reference.get_communicator();
    check_equal(indent +
                  "cells unlike deal.II's fully distributed triangulation",
                Utilities::MPI::sum(differences, comm),
                0);
    check_equal(indent + "coarse cells looked up wrong",
                Utilities::MPI::sum(wrong_lookups, comm),
                0);
  }

  /// The last rank owns no cell (deal.II gives it one artificial cell):
  /// DistributedTriangulation, with the table and with the search, against
  /// deal.II's own.
  void
  check_rank_without_cells(const Scene &scene)
  {
    const MPI_Comm     comm    = MPI_COMM_WORLD;
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    Triangulation<3>   partitioned;
    partitioned.copy_triangulation(scene.triangulation);
    const std::uint64_t n_cells = partitioned.n_active_cells();
    for (const auto &cell : partitioned.active_cell_iterators())
      cell->set_subdomain_id(static_cast<types::subdomain_id>(
        std::uint64_t(cell->active_cell_index()) * (n_ranks - 1) / n_cells));
    const auto description = TriangulationDescription::Utilities::
      create_description_from_triangulation(partitioned, comm);
    parallel::fullydistributed::Triangulation<3> reference(comm);
    reference.create_triangulation(description);
    DistributedTriangulation table(comm), searched(comm, false);
    table.create_triangulation(description);
    searched.create_triangulation(description);
    deallog << "the last rank without cells:" << std::endl;
    check_equal("  locally owned cells of the last rank",
                Utilities::MPI::broadcast(comm,
                                          table.n_locally_owned_active_cells(),
                                          n_ranks - 1),
                0);
    check_against_dealii("  ", reference, {&table, &searched});
  }

  /// Scatter of @p serial into @p distributed, then gather, gives it back
  /// exactly.
  void
  check_scatter_gather(const DistributedLayout       &layout,
                       const Vector<double>          &serial,
                       TrilinosWrappers::MPI::Vector &distributed)
  {
    layout.scatter(serial, distributed);
    Vector<double> back = layout.gather(distributed);
    back -= serial;
    check_below("  scatter then gather, largest difference",
                back.linfty_norm(),
                0.);
  }

  /// The layout of @p scene checked against it; with @p layout_scene, the
  /// layout is built from that scene instead, in groups of @p group_size
  /// ranks (its members' copy of the scene may lack the mesh).
  void
  check_layout(const std::string                   &name,
               const Scene                         &scene,
               const DistributedLayout::Partitioner partitioner,
               const bool                           print_per_rank,
               const Scene                         *layout_scene = nullptr,
               const unsigned int                   group_size   = 1)
  {
    const MPI_Comm          comm    = MPI_COMM_WORLD;
    const unsigned int      n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const DistributedLayout layout(layout_scene ? *layout_scene : scene,
                                   comm,
                                   partitioner,
                                   group_size);
    const auto                   &owned  = layout.locally_owned_dofs;
    const types::global_dof_index n_dofs = scene.dof_handler.n_dofs();

    deallog << name << ':' << std::endl;
    check_equal("  DoFs", layout.dof_handler.n_dofs(), n_dofs);

    // Every serial DoF owned by exactly one rank.
    std::vector<double> owners(n_dofs, 0.);
    for (const auto dof : owned)
      owners[layout.serial_dof(dof)] += 1.;
    Utilities::MPI::sum(owners, comm, owners);
    check_equal("  serial DoFs not owned by exactly one rank",
                std::count_if(owners.begin(),
                              owners.end(),
                              [](const double n) { return n != 1.; }),
                0);

    // A rank's locally relevant DoF sits where its serial DoF sits, and is
    // the same component.
    std::map<types::global_dof_index, Point<3>> points, serial_points;
    DoFTools::map_dofs_to_support_points(scene.mapping,
                                         layout.dof_handler,
                                         points);
    DoFTools::map_dofs_to_support_points(scene.mapping,
                                         scene.dof_handler,
                                         serial_points);
    double       largest_distance = 0.;
    unsigned int wrong_components = 0;
    for (const auto &[dof, point] : points)
      {
        const auto serial = layout.serial_dof(dof);
        largest_distance =
          std::max(largest_distance, point.distance(serial_points.at(serial)));
        // Both layouts number a vertex's three components together.
        wrong_components += dof % 3 != serial % 3;
      }
    check_below("  largest distance of a rank's DoF to its serial DoF (mm)",
                Utilities::MPI::max(largest_distance, comm),
                0.);
    check_equal("  DoFs mapped to another component",
                Utilities::MPI::sum(wrong_components, comm),
                0);

    // Join points per segment, decided per owned DoF (first component).
    std::vector<unsigned int> vertex_of_dof(n_dofs);
    for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
      if (scene.vertex_dofs()[v][0] != numbers::invalid_dof_index)
        for (const auto dof : scene.vertex_dofs()[v])
          vertex_of_dof[dof] = v;
    const unsigned int        n_segments = scene.segments.size();
    std::vector<unsigned int> mine(n_segments, 0);
    unsigned int              join_dofs = 0;
    for (const auto dof : owned)
      if (layout.is_join_dof(dof))
        {
          ++join_dofs;
          const auto serial = layout.serial_dof(dof);
          if (serial % 3 == 0)
            ++mine[scene.vertex_segment()[vertex_of_dof[serial]]];
        }
    // Every locally relevant DoF, owned or ghost, has the segment of the
    // serial vertex it maps to.
    unsigned int other_segment = 0;
    for (const auto dof : layout.locally_relevant_dofs)
      other_segment +=
        layout.join_segment_of_dof(dof) !=
        scene.vertex_segment()[vertex_of_dof[layout.serial_dof(dof)]];
    check_equal("  relevant DoFs whose segment is not the serial vertex's",
                Utilities::MPI::sum(other_segment, comm),
                0);
    check_equal("  vertices touching two segments' bone, on all ranks",
                Utilities::MPI::sum(layout.n_owned_shared_join_points(), comm),
                scene.n_shared_join_points);
    check_equal("  join DoFs on all ranks",
                Utilities::MPI::sum(join_dofs, comm),
                std::count(scene.join_dofs().begin(),
                           scene.join_dofs().end(),
                           true));
    const auto per_rank = Utilities::MPI::gather(comm, mine);
    for (unsigned int s = 0; s < n_segments; ++s)
      {
        unsigned int total = 0, ranks_with_none = 0;
        if (Utilities::MPI::this_mpi_process(comm) == 0)
          for (unsigned int r = 0; r < n_ranks; ++r)
            {
              total += per_rank[r][s];
              ranks_with_none += per_rank[r][s] == 0;
            }
        total           = Utilities::MPI::broadcast(comm, total);
        ranks_with_none = Utilities::MPI::broadcast(comm, ranks_with_none);
        check_equal("  join points of '" + scene.segments[s].name + "'",
                    total,
                    scene.n_join_vertices(s));
        if (print_per_rank)
          {
            deallog << "    per rank:";
            if (Utilities::MPI::this_mpi_process(comm) == 0)
              for (unsigned int r = 0; r < n_ranks; ++r)
                deallog << ' ' << per_rank[r][s];
            deallog << " (" << ranks_with_none << " ranks own none)"
                    << std::endl;
          }
      }

    // The triangulation against deal.II's own, from the same description.
    {
      Triangulation<3> partitioned;
      partitioned.copy_triangulation(scene.triangulation);
      // Each cell's rank as the layout has it: gathered from the owners.
      std::vector<unsigned int> owner(scene.triangulation.n_active_cells(), 0);
      for (const auto &cell : layout.triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          owner[cell->id().get_coarse_cell_id()] =
            Utilities::MPI::this_mpi_process(comm);
      Utilities::MPI::sum(owner, comm, owner);
      for (const auto &cell : partitioned.active_cell_iterators())
        cell->set_subdomain_id(owner[cell->active_cell_index()]);
      const auto description = TriangulationDescription::Utilities::
        create_description_from_triangulation(partitioned, comm);

      // The layout's part of every rank, as any rank describes it from the
      // mesh without a copy, is deal.II's description of it.
      std::vector<types::subdomain_id> owners(owner.begin(), owner.end());
      unsigned int                     unlike_dealii = 0;
      for (unsigned int r = 0; r < n_ranks; ++r)
        unlike_dealii +=
          !(tetrahedra_only(
              describe_part(scene.triangulation, owners, r, comm)) ==
            tetrahedra_only(
              TriangulationDescription::Utilities::
                create_description_from_triangulation(
                  partitioned,
                  comm,
                  TriangulationDescription::Settings::default_setting,
                  r)));
      check_equal("  parts described unlike deal.II's description",
                  Utilities::MPI::sum(unlike_dealii, comm),
                  0);
      // All ranks' parts in one walk, as a group's root describes them.
      const auto together =
        describe_parts(scene.triangulation, owners, 0, n_ranks, comm);
      unsigned int unlike_alone = 0;
      for (unsigned int r = 0; r < n_ranks; ++r)
        unlike_alone += !(
          tetrahedra_only(together[r]) ==
          tetrahedra_only(describe_part(scene.triangulation, owners, r, comm)));
      check_equal("  parts described together unlike described alone",
                  unlike_alone,
                  0);
      // The owners are those of deal.II's partition of the whole mesh
      // (METIS on its face graph, or the cell order's ranges).
      if (partitioner == DistributedLayout::Partitioner::metis)
        GridTools::partition_triangulation(n_ranks,
                                           partitioned,
                                           SparsityTools::Partitioner::metis);
      else
        for (const auto &cell : partitioned.active_cell_iterators())
          cell->set_subdomain_id(static_cast<types::subdomain_id>(
            std::uint64_t(cell->active_cell_index()) * n_ranks /
            partitioned.n_active_cells()));
      unsigned int other_owner = 0;
      for (const auto &cell : partitioned.active_cell_iterators())
        other_owner += cell->subdomain_id() != owner[cell->active_cell_index()];
      check_equal("  cells whose rank is not deal.II's partition's",
                  other_owner,
                  0);

      parallel::fullydistributed::Triangulation<3> reference(comm);
      reference.create_triangulation(description);
      DistributedTriangulation searched(comm, /*allow_table=*/false);
      searched.create_triangulation(description);
      const unsigned int with_table = Utilities::MPI::sum<unsigned int>(
        layout.triangulation.has_index_table(), comm);
      deallog << "  ranks looking coarse cells up in a table: " << with_table
              << " of " << n_ranks << std::endl;

      check_against_dealii("  ", reference, {&layout.triangulation, &searched});
    }

    // Scatter and gather give a serial field back exactly.
    Vector<double> serial(n_dofs);
    for (const auto &[dof, point] : serial_points)
      serial[dof] = field(point, dof % 3);
    TrilinosWrappers::MPI::Vector distributed(owned, comm);
    check_scatter_gather(layout, serial, distributed);

    // A field set on the ranks from their own support points gathers to the
    // serial field.
    for (const auto dof : owned)
      distributed[dof] = field(points.at(dof), dof % 3);
    distributed.compress(VectorOperation::insert);
    Vector<double> back = layout.gather(distributed);
    back -= serial;
    check_below("  field set on the ranks, gathered, largest difference",
                back.linfty_norm(),
                0.);
  }
  /// The effects' tissues and nodal body force decided on the ranks, from
  /// their own and ghost cells, against the scene's arrays.
  void
  check_effects(const std::string                   &name,
                const Scene                         &scene,
                const DistributedLayout::Partitioner partitioner,
                const unsigned int                   group_size = 1)
  {
    const MPI_Comm          comm = MPI_COMM_WORLD;
    const DistributedLayout layout(scene, comm, partitioner, group_size);
    deallog << name << ':' << std::endl;
    unsigned int other_tissue = 0, owned_cells = 0;
    for (const auto &cell : layout.dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          owned_cells += cell->is_locally_owned();
          other_tissue +=
            layout.tissue_of_cell(cell) !=
            scene.tissue_of_cell(DistributedLayout::serial_cell_index(cell));
        }
    check_equal("  own and ghost cells whose tissue is not the serial cell's",
                Utilities::MPI::sum(other_tissue, comm),
                0);
    check_equal("  owned cells, on all ranks",
                Utilities::MPI::sum(owned_cells, comm),
                scene.triangulation.n_active_cells());
    double largest = 0., difference = 0.;
    for (const auto dof : layout.locally_owned_dofs)
      {
        const double serial = scene.effects.body_force[layout.serial_dof(dof)];
        largest             = std::max(largest, std::abs(serial));
        difference =
          std::max(difference, std::abs(layout.body_force()[dof] - serial));
      }
    largest = Utilities::MPI::max(largest, comm);
    check_above("  largest serial nodal body force (N)", largest, 1e-6);
    // The same cells in the same order, summed alike: the same bits.
    check_below("  largest difference of an owned DoF's body force (N)",
                Utilities::MPI::max(difference, comm),
                0.);
  }
} // namespace

SOFTFACE_TEST(distributed_layout)
{
  using Partitioner = DistributedLayout::Partitioner;
  deallog << "ranks: " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
          << std::endl;

  Scene cube;
  make_cube_scene(cube, 3000);
  check_layout("generated cube, cell order",
               cube,
               Partitioner::cell_order,
               true);
  // METIS's parts may change with its version: the counts per rank are not
  // printed.
  check_layout("generated cube, metis", cube, Partitioner::metis, false);
  check_rank_without_cells(cube);

  // Two tetrahedra, the first a bone segment's: on 3 ranks the cell order
  // leaves the last rank without cells, alone and in a group (its root
  // sends it an empty part).
  {
    Scene two;
    {
      const std::vector<Point<3>> vertices = {
        {0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {0, 0, -10}};
      std::vector<CellData<3>> cells(2, CellData<3>(4));
      cells[0].vertices    = {0, 1, 2, 3};
      cells[0].material_id = 5;
      cells[1].vertices    = {0, 2, 1, 4};
      two.triangulation.create_triangulation(vertices, cells, SubCellData());
      two.mesh_description = "two tetrahedra";
      two.segments         = {{"bone", {5}, {}, {}}};
      two.setup();
    }
    for (const unsigned int group_size : {1u, 3u})
      {
        const MPI_Comm          comm = MPI_COMM_WORLD;
        const DistributedLayout layout(two,
                                       comm,
                                       Partitioner::cell_order,
                                       group_size);
        deallog << "two tetrahedra, groups of " << group_size << ':'
                << std::endl;
        deallog << "  ranks without cells: "
                << Utilities::MPI::sum<unsigned int>(
                     layout.triangulation.n_locally_owned_active_cells() == 0,
                     comm)
                << std::endl;
        check_equal("  owned DoFs on all ranks",
                    Utilities::MPI::sum(layout.locally_owned_dofs.n_elements(),
                                        comm),
                    two.dof_handler.n_dofs());
        Vector<double> serial(two.dof_handler.n_dofs());
        for (unsigned int i = 0; i < serial.size(); ++i)
          serial[i] = 1. + i;
        TrilinosWrappers::MPI::Vector distributed(layout.locally_owned_dofs,
                                                  comm);
        check_scatter_gather(layout, serial, distributed);
      }
  }

  // Segments that share vertices (make_cube_with_shared_join_points()).
  Scene shared;
  make_cube_with_shared_join_points(shared, 3000);
  check_layout("generated cube, segments sharing vertices, metis",
               shared,
               Partitioner::metis,
               false);

  // Where the scene does not leave such vertices free, every rank refuses
  // them with one message (here the scene allowed them first).
  shared.resolve_shared_join_points = false;
  unsigned int refused              = 0;
  try
    {
      const DistributedLayout layout(shared, MPI_COMM_WORLD);
    }
  catch (const Error &error)
    {
      ++refused;
      deallog << "refused: " << error.what() << std::endl;
    }
  check_equal("ranks that refused shared join points",
              Utilities::MPI::sum(refused, MPI_COMM_WORLD),
              Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));

  // 70 parts described in one call (two walks of up to 64) equal each
  // described alone, with the vertices' indices in the mesh.
  {
    const unsigned int               n_parts = 70;
    std::vector<types::subdomain_id> owners(
      cube.triangulation.n_active_cells());
    for (unsigned int c = 0; c < owners.size(); ++c)
      owners[c] = (c * 37) % n_parts;
    std::vector<std::vector<unsigned int>> vertices;
    const auto                             parts = describe_parts(
      cube.triangulation, owners, 0, n_parts, MPI_COMM_WORLD, &vertices);
    unsigned int unlike = 0, empty = 0;
    for (unsigned int r = 0; r < n_parts; ++r)
      {
        std::vector<unsigned int> alone_vertices;
        const auto                alone = describe_part(
          cube.triangulation, owners, r, MPI_COMM_WORLD, &alone_vertices);
        unlike += !(tetrahedra_only(parts[r]) == tetrahedra_only(alone)) ||
                  vertices[r] != alone_vertices;
        empty += parts[r].coarse_cells.empty();
      }
    deallog << "70 parts of the cube:" << std::endl;
    check_equal("  described together unlike alone", unlike, 0);
    check_equal("  empty parts", empty, 0);

    // Parts on both sides of the 64-part chunks against deal.II's own
    // description of a copy with these owners, and parts described from a
    // first rank other than 0.
    Triangulation<3> partitioned;
    partitioned.copy_triangulation(cube.triangulation);
    for (const auto &cell : partitioned.active_cell_iterators())
      cell->set_subdomain_id(owners[cell->active_cell_index()]);
    unsigned int unlike_dealii = 0;
    for (const unsigned int r : {0u, 63u, 64u, 69u})
      unlike_dealii += !(
        tetrahedra_only(parts[r]) ==
        tetrahedra_only(TriangulationDescription::Utilities::
                          create_description_from_triangulation(
                            partitioned,
                            MPI_COMM_WORLD,
                            TriangulationDescription::Settings::default_setting,
                            r)));
    check_equal("  parts 0, 63, 64, 69 unlike deal.II's description",
                unlike_dealii,
                0);
    const auto from_3 =
      describe_parts(cube.triangulation, owners, 3, 67, MPI_COMM_WORLD);
    unsigned int unlike_from_3 = 0;
    for (unsigned int r = 3; r < n_parts; ++r)
      unlike_from_3 +=
        !(tetrahedra_only(from_3[r - 3]) == tetrahedra_only(parts[r]));
    check_equal("  parts 3 to 69 described from part 3 on unlike from 0",
                unlike_from_3,
                0);

    // A part sent as plain arrays arrives whole (every field compared,
    // faces' boundary ids and manifold ids too), with its vertices' indices;
    // a message cut short is refused.
    unsigned int unlike_sent = 0;
    for (const unsigned int r : {0u, 64u})
      {
        std::vector<unsigned int> received;
        auto back = unpack_part(pack_part(parts[r], vertices[r]),
                                MPI_COMM_WORLD,
                                received);
        unlike_sent += !(tetrahedra_only(back) == tetrahedra_only(parts[r])) ||
                       received != vertices[r];
      }
    check_equal("  parts sent unlike described", unlike_sent, 0);
    auto cut = pack_part(parts[1], vertices[1]);
    cut.resize(cut.size() - 5);
    unsigned int refused_cut = 0;
    try
      {
        std::vector<unsigned int> received;
        unpack_part(cut, MPI_COMM_WORLD, received);
      }
    catch (const ExceptionBase &)
      {
        ++refused_cut;
      }
    check_equal("  a message cut short refused", refused_cut, 1);
  }

  // Two tissues under gravity, the upper half denser: each rank decides
  // its cells' tissues and its vertices' loads by the effects' rules.
  Scene layered;
  make_two_tissue_cube(layered, false);
  apply_effect(layered,
               "gravity",
               {{"Gravity", "1, 2, -9.81"},
                {"Density", "1000"},
                {"Densities", "3: 1100"}});
  check_effects("two tissues under gravity, cell order",
                layered,
                Partitioner::cell_order);
  check_effects("two tissues under gravity, metis",
                layered,
                Partitioner::metis);
  check_effects("two tissues under gravity, cell order, in one group",
                layered,
                Partitioner::cell_order,
                Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));

  // A body force on the last rank only (as if a member had been sent
  // another scene): every rank stops before the collective that would wait.
  {
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    Scene uneven;
    make_two_tissue_cube(uneven, false);
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == n_ranks - 1)
      apply_effect(uneven, "gravity", {{"Gravity", "0, 0, -9.81"}});
    int stopped = 0;
    try
      {
        const DistributedLayout layout(uneven, MPI_COMM_WORLD);
      }
    catch (const ExceptionBase &e)
      {
        stopped =
          std::string(e.what()).find("The ranks disagree on the body force") !=
          std::string::npos;
      }
    deallog << "a body force on the last rank only:" << std::endl;
    check_equal("  ranks that stop with the message",
                Utilities::MPI::sum(stopped, MPI_COMM_WORLD),
                int(n_ranks));
  }

  ParameterHandler prm;
  Scene            gmsh;
  read_scene("peer_calculix_cube30k.prm", prm, gmsh);
  check_layout("gmsh cube30k, cell order", gmsh, Partitioner::cell_order, true);
  check_layout("gmsh cube30k, metis", gmsh, Partitioner::metis, false);

  // In groups of two ranks (one group on 2 ranks, a group of two and one of
  // one on 3), each group's root describes its members' parts: the members'
  // scene has no mesh and no serial DoFHandler left, so that a layout that
  // read them would fail. Its parts are checked against the whole scene.
  {
    const unsigned int group_size = 2;
    const bool         member =
      Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) % group_size != 0;
    Scene stripped;
    read_scene("peer_calculix_cube30k.prm", prm, stripped);
    if (member)
      {
        stripped.dof_handler.clear();
        stripped.triangulation.clear();
      }
    check_equal("members' scene cells, summed over the ranks",
                Utilities::MPI::sum(stripped.triangulation.n_active_cells(),
                                    MPI_COMM_WORLD),
                (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) + 1) /
                  group_size * gmsh.triangulation.n_active_cells());
    check_layout("gmsh cube30k, metis, in groups of 2, members without mesh",
                 gmsh,
                 Partitioner::metis,
                 false,
                 &stripped,
                 group_size);
  }
}

// The scene as points and their neighbours: what the mass tensor and mass
// spring models work on and what the P1 sparsity of the points is built from.

#include <deal.II/base/array_view.h>

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/core/point_mesh.h>
#include <softface/core/sub_communicator.h>

#include <algorithm>

namespace softface
{
  PointMesh::PointMesh(const Scene       &scene,
                       const std::string &model,
                       const MPI_Comm     communicator)
  {
    if (!scene.dofs_are_point_blocks())
      throw Error(model + ": the DoFs of a vertex are not a block "
                          "3p, 3p+1, 3p+2 (renumbered DoFs?).");
    const unsigned int n = scene.n_dofs() / 3;

    position.assign(n, Point<3>());
    is_free.assign(n, false);
    for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
      {
        const auto &dofs = scene.vertex_dofs()[v];
        if (dofs[0] == numbers::invalid_dof_index)
          continue;
        position[dofs[0] / 3] = scene.vertices()[v];
        is_free[dofs[0] / 3]  = !scene.join_dofs()[dofs[0]];
      }

    tetrahedra.clear();
    tissue.clear();
    if (scene.has_cells())
      {
        tetrahedra.reserve(scene.triangulation.n_active_cells());
        tissue.reserve(scene.triangulation.n_active_cells());
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          {
            std::array<unsigned int, 4> p;
            for (unsigned int a = 0; a < 4; ++a)
              p[a] = scene.vertex_dofs()[cell->vertex_index(a)][0] / 3;
            tetrahedra.push_back(p);
            tissue.push_back(scene.tissue_of_cell(tissue.size()));
          }
      }
    // Ranks without cells get them from rank 0, which must have them.
    // Decided together: does any rank lack cells, does rank 0?
    const bool sends    = Utilities::MPI::this_mpi_process(communicator) == 0;
    const int  local[2] = {!scene.has_cells(), sends && !scene.has_cells()};
    int        lacking[2];
    Utilities::MPI::max(ArrayView<const int>(local, 2),
                        communicator,
                        ArrayView<int>(lacking, 2));
    if (lacking[1] != 0)
      throw Error(model + ": rank 0 of its MPI ranks holds none of the "
                          "scene's cells to send the others.");
    // A constrained step reads the constraints' cells (the simulator
    // keeps every rank's cells with them).
    if (lacking[0] != 0 && scene.has_vertex_constraints())
      throw Error(model + ": vertex constraints (sliding contact, "
                          "separated lips) need the scene's cells on "
                          "every MPI rank.");
    if (lacking[0] != 0)
      {
        const SubCommunicator receivers(communicator,
                                        sends || !scene.has_cells());
        if (receivers.communicator != MPI_COMM_NULL)
          {
            if (!sends)
              {
                tetrahedra.resize(scene.n_cells());
                tissue.resize(scene.n_cells());
              }
            static_assert(sizeof(tetrahedra[0]) == 4 * sizeof(unsigned int),
                          "tetrahedra are sent as a plain array");
            Utilities::MPI::broadcast(reinterpret_cast<unsigned int *>(
                                        tetrahedra.data()),
                                      4 * tetrahedra.size(),
                                      0,
                                      receivers.communicator);
            Utilities::MPI::broadcast(tissue.data(),
                                      tissue.size(),
                                      0,
                                      receivers.communicator);
          }
      }

    // The tetrahedra of every point (CSR), then each point's neighbours
    // once each (a mark per point) and sorted: sorting every tetrahedron's
    // entry of a neighbour (about 68 per point, 14 of them distinct) took
    // 4.7 times as long on a gmsh mesh as on the generated cube, whose
    // entries come nearly in order.
    tet_start.assign(n + 1, 0);
    for (const auto &p : tetrahedra)
      for (const unsigned int a : p)
        ++tet_start[a + 1];
    for (unsigned int j = 0; j < n; ++j)
      tet_start[j + 1] += tet_start[j];
    tets_of_point.resize(tet_start[n]);
    {
      auto next = tet_start;
      for (unsigned int t = 0; t < tetrahedra.size(); ++t)
        for (const unsigned int a : tetrahedra[t])
          tets_of_point[next[a]++] = t;
    }
    row_start.assign(n + 1, 0);
    neighbour.clear();
    neighbour.reserve(std::size_t(tet_start[n]) * 3 / 4);
    std::vector<unsigned int> mark(n, numbers::invalid_unsigned_int);
    for (unsigned int j = 0; j < n; ++j)
      {
        const std::size_t row = neighbour.size();
        for (unsigned int i = tet_start[j]; i < tet_start[j + 1]; ++i)
          for (const unsigned int k : tetrahedra[tets_of_point[i]])
            if (k != j && mark[k] != j)
              {
                mark[k] = j;
                neighbour.push_back(k);
              }
        std::sort(neighbour.begin() + row, neighbour.end());
        row_start[j + 1] = neighbour.size();
      }
  }

  unsigned int
  PointMesh::n_points() const
  {
    return position.size();
  }

  unsigned int
  PointMesh::edge_index(const unsigned int j, const unsigned int k) const
  {
    const unsigned int index = row_start[j] + neighbours_before(j, k);
    Assert(index < row_start[j + 1] && neighbour[index] == k,
           ExcMessage("not a neighbour"));
    return index;
  }

  unsigned int
  PointMesh::neighbours_before(const unsigned int j, const unsigned int k) const
  {
    // Counted without a branch: a binary search over a row of about 14
    // mispredicts its branches on an irregular mesh (6 times the
    // generated cube's cost on a gmsh mesh).
    unsigned int before = 0;
    for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
      before += neighbour[i] < k;
    return before;
  }
} // namespace softface

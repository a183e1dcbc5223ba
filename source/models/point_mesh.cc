// The scene as points and neighbours (models): the setup that the mass tensor
// and mass spring models share.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/models/point_mesh.h>

#include <algorithm>

namespace softface
{
  namespace Models
  {
    PointMesh::PointMesh(const Scene &scene, const std::string &model)
    {
      if (!scene.dofs_are_point_blocks())
        throw Error(model + ": the DoFs of a vertex are not a block "
                            "3p, 3p+1, 3p+2 (renumbered DoFs?).");
      const unsigned int n = scene.dof_handler.n_dofs() / 3;

      position.assign(n, Point<3>());
      is_free.assign(n, false);
      for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
        {
          const auto &dofs = scene.vertex_dofs()[v];
          if (dofs[0] == numbers::invalid_dof_index)
            continue;
          position[dofs[0] / 3] = scene.triangulation.get_vertices()[v];
          is_free[dofs[0] / 3]  = !scene.join_dofs()[dofs[0]];
        }

      tetrahedra.clear();
      tetrahedra.reserve(scene.triangulation.n_active_cells());
      for (const auto &cell : scene.triangulation.active_cell_iterators())
        {
          std::array<unsigned int, 4> p;
          for (unsigned int a = 0; a < 4; ++a)
            p[a] = scene.vertex_dofs()[cell->vertex_index(a)][0] / 3;
          tetrahedra.push_back(p);
        }

      // Neighbours of every point, sorted, then the CSR structure.
      std::vector<std::vector<unsigned int>> adjacent(n);
      for (const auto &p : tetrahedra)
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int b = 0; b < 4; ++b)
            if (a != b)
              adjacent[p[a]].push_back(p[b]);
      row_start.assign(n + 1, 0);
      neighbour.clear();
      for (unsigned int j = 0; j < n; ++j)
        {
          auto &a = adjacent[j];
          std::sort(a.begin(), a.end());
          a.erase(std::unique(a.begin(), a.end()), a.end());
          neighbour.insert(neighbour.end(), a.begin(), a.end());
          row_start[j + 1] = neighbour.size();
          std::vector<unsigned int>().swap(a);
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
      const auto begin = neighbour.begin() + row_start[j];
      const auto end   = neighbour.begin() + row_start[j + 1];
      const auto it    = std::lower_bound(begin, end, k);
      Assert(it != end && *it == k, ExcMessage("not a neighbour"));
      return it - neighbour.begin();
    }
  } // namespace Models
} // namespace softface

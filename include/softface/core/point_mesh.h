#ifndef softface_core_point_mesh_h
#define softface_core_point_mesh_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <softface/core/scene.h>
#include <softface/core/tetrahedron.h>

#include <array>
#include <string>
#include <vector>

namespace softface
{
  /**
   * The scene seen as points and their neighbours, what the point-based
   * models (mass tensor, mass spring) work on. Point p is the vertex whose
   * DoFs on the shared layout are 3p, 3p+1, 3p+2 (deal.II's numbering of
   * FESystem(FE_SimplexP(1), 3) unless renumbered), so a model's vector of
   * point displacements is a displacement vector on the shared layout.
   *
   * It holds all a point model reads of the cells (their points, tissues
   * and the vertices' positions), so that on several MPI ranks a rank
   * whose scene holds no cells (Scene::has_cells()) runs the
   * model on the points alone: rank 0 of the model's communicator sends
   * it the tetrahedra and their tissues (17 bytes a cell, where the
   * scene's triangulation and DoFs cost about 360: see
   * doc/results/scaling_groups_points.md).
   */
  struct PointMesh
  {
    /// Throws an error naming @p model if the DoFs are not point blocks.
    /// Collective on @p communicator; where some of its ranks hold no
    /// cells, rank 0 must hold them and the scene may have no vertex
    /// constraints (an error on every rank otherwise).
    PointMesh(const Scene       &scene,
              const std::string &model,
              const MPI_Comm     communicator = MPI_COMM_SELF);

    unsigned int
    n_points() const;

    /// The reference positions of tetrahedron @p t's points, in the order
    /// of its cell's vertices.
    Tetrahedron::Vertices
    vertices(const unsigned int t) const
    {
      const auto &p = tetrahedra[t];
      return {{position[p[0]], position[p[1]], position[p[2]], position[p[3]]}};
    }

    /// Index into neighbour[] of the edge (j, k); k must be a neighbour.
    unsigned int
    edge_index(const unsigned int j, const unsigned int k) const;

    /// The neighbours of point j before point k (any k).
    unsigned int
    neighbours_before(const unsigned int j, const unsigned int k) const;

    /// The points of every tetrahedron, in the order of the mesh's cells.
    std::vector<std::array<unsigned int, 4>> tetrahedra;
    /// The tissue of every tetrahedron (Scene::tissue_of_cell()).
    std::vector<unsigned char> tissue;
    /// Reference positions.
    std::vector<Point<3>> position;
    /// False for join points.
    std::vector<bool> is_free;
    /// The neighbours of point j, ascending, are neighbour[row_start[j]
    /// .. row_start[j + 1]) (every point sharing a tetrahedron with j).
    std::vector<unsigned int> row_start;
    std::vector<unsigned int> neighbour;
    /// The tetrahedra around point j are tets_of_point[tet_start[j] ..
    /// tet_start[j + 1]) (indices into tetrahedra, ascending).
    std::vector<unsigned int> tet_start;
    std::vector<unsigned int> tets_of_point;
  };
} // namespace softface

#endif

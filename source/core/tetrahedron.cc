// Geometry of one straight-sided tetrahedron (core): Jacobian, P1 shape
// gradients, volume and reference coordinates, used by the mesh checks, the
// elasticity kernels (fe/), the mass spring model and point evaluation.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/tetrahedron.h>

namespace softface
{
  namespace Tetrahedron
  {
    Vertices
    vertices(const Triangulation<3>::active_cell_iterator &cell)
    {
      return {
        {cell->vertex(0), cell->vertex(1), cell->vertex(2), cell->vertex(3)}};
    }

    Tensor<2, 3>
    jacobian(const Vertices &x)
    {
      Tensor<2, 3> J;
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int d = 0; d < 3; ++d)
          J[d][k] = x[k + 1][d] - x[0][d];
      return J;
    }

    Geometry
    geometry(const Vertices &x)
    {
      const Tensor<2, 3> J         = jacobian(x);
      const Tensor<2, 3> J_inverse = invert(J);
      Geometry           g;
      for (unsigned int a = 1; a < 4; ++a)
        g.gradients[a] = J_inverse[a - 1];
      g.gradients[0] = -(g.gradients[1] + g.gradients[2] + g.gradients[3]);
      g.volume       = determinant(J) / 6.;
      return g;
    }

    Point<3>
    reference_coordinates(const Vertices &x, const Point<3> &p)
    {
      return Point<3>(invert(jacobian(x)) * (p - x[0]));
    }
  } // namespace Tetrahedron
} // namespace softface

#ifndef softface_core_tetrahedron_h
#define softface_core_tetrahedron_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <array>

namespace softface
{
  using namespace dealii;

  /**
   * The geometry of one straight-sided tetrahedron, written once for every
   * part of softface that needs it: mesh checks, the P1 elasticity kernels,
   * the mass spring model's inversion check, point location. The Jacobian's
   * columns are the edges from vertex 0, so the rows of its inverse are the
   * (constant) gradients of the barycentric shape functions 1..3, and a
   * point's reference coordinates are its barycentric coordinates 1..3
   * (deal.II's reference tetrahedron has vertices 0, e_x, e_y, e_z).
   */
  namespace Tetrahedron
  {
    using Vertices = std::array<Point<3>, 4>;

    /// The vertices of a cell in deal.II's order.
    Vertices
    vertices(const Triangulation<3>::active_cell_iterator &cell);

    /// Signed volume (positive for deal.II's orientation).
    inline double
    signed_volume(const Vertices &x)
    {
      return cross_product_3d(x[1] - x[0], x[2] - x[0]) * (x[3] - x[0]) / 6.;
    }

    /// J with columns x_k - x_0 (k = 1, 2, 3).
    Tensor<2, 3>
    jacobian(const Vertices &x);

    /// What the P1 kernels need of a tetrahedron in its reference position.
    struct Geometry
    {
      /// Gradients of the four barycentric (P1) shape functions.
      std::array<Tensor<1, 3>, 4> gradients;
      /// Signed volume.
      double volume = 0.;
    };

    Geometry
    geometry(const Vertices &x);

    /// Reference (barycentric 1..3) coordinates of @p p.
    Point<3>
    reference_coordinates(const Vertices &x, const Point<3> &p);
  } // namespace Tetrahedron
} // namespace softface

#endif

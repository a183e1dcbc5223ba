// The pieces of the accuracy benchmark's quadratic reference:
// 1. forces and tangent by quadrature (Hyperelasticity::assemble) on the
//    P1 layout equal the closed-form P1 ones to 1e-12 (all three laws,
//    distorted mesh, strains of several percent);
// 2. a homogeneous deformation u = G x prescribed on every join point is an
//    equilibrium of every hyperelastic law, and lies in the quadratic space:
//    the degree-2 model must return it to 1e-8 at the vertices and, through
//    PointEvaluation of its quadratic field, at points inside the cells
//    (Neo-Hooke with direct and cg amg, the linear law with direct); the
//    P1 field interpolated there must too.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/grid/grid_tools.h>

#include <softface/models/nonlinear_fem.h>
#include <softface/core/error.h>
#include <softface/fe/point_evaluation.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  Point<3>
  bulge(const Point<3> &x)
  {
    const double s = std::sin(M_PI * x[0] / 80) * std::sin(M_PI * x[1] / 80) *
                     std::sin(M_PI * x[2] / 80);
    return x + Point<3>(4. * s, -3. * s, 2. * s);
  }
} // namespace

SOFTFACE_TEST(quadratic_reference)
{
  Scene                scene;
  Mesh::CubeParameters cube;
  cube.target_n_tetrahedra = 400;
  Mesh::generate_cube(cube, scene.triangulation);
  GridTools::transform(bulge, scene.triangulation);
  scene.segments = {{"fixed", {}, {Mesh::cube_outer_face}},
                    {"bone", {Mesh::cube_inner_id}, {}}};
  scene.setup();
  const unsigned int n = scene.dof_handler.n_dofs();

  // 1. Quadrature assembly on P1 = closed form.
  Vector<double> u(n);
  for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
    for (unsigned int c = 0; c < 3; ++c)
      {
        const Point<3> &x = scene.triangulation.get_vertices()[v];
        u[scene.vertex_dofs()[v][c]] =
          1.5 * std::sin(0.05 * x[0] + c) * std::cos(0.07 * x[1] - 0.3 * c) +
          0.02 * x[(c + 1) % 3];
      }
  for (const std::string law : {"st venant-kirchhoff", "neo-hooke", "linear"})
    {
      Models::NonlinearFEM model;
      model.set_options(law, "direct");
      model.setup(scene);
      SparseMatrix<double> closed(model.sparsity_pattern()),
        quadrature(model.sparsity_pattern());
      Vector<double> f_closed, f_quadrature;
      model.evaluate(u, f_closed, &closed);
      Hyperelasticity::assemble(Hyperelasticity::law_from_name(law),
                                scene.material.lambda(),
                                scene.material.mu(),
                                scene.mapping,
                                scene.dof_handler,
                                QGaussSimplex<3>(1),
                                u,
                                f_quadrature,
                                &quadrature);
      f_quadrature -= f_closed;
      quadrature.add(-1., closed);
      deallog << law << ": |f| > 0: " << (f_closed.l2_norm() > 0) << std::endl;
      softface_tests::check(f_quadrature.l2_norm() <= 1e-12 * f_closed.l2_norm(),
                            law + ": quadrature forces = closed form");
      softface_tests::check(quadrature.frobenius_norm() <=
                              1e-12 * closed.frobenius_norm(),
                            law + ": quadrature tangent = closed form");
    }

  // 2. Homogeneous deformation with the quadratic model.
  Tensor<2, 3> G;
  G[0][0] = 0.05, G[0][1] = 0.02, G[1][1] = -0.03, G[1][2] = 0.04;
  G[2][0] = -0.02, G[2][2] = 0.06;
  Vector<double> prescribed(n);
  for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
    if (scene.vertex_segment()[v] != numbers::invalid_unsigned_int)
      for (unsigned int c = 0; c < 3; ++c)
        prescribed[scene.vertex_dofs()[v][c]] =
          (G * scene.triangulation.get_vertices()[v])[c];

  // Points inside cells: the centroid and a point near a face of every
  // tenth cell.
  std::vector<Point<3>> points;
  unsigned int          i = 0;
  for (const auto &cell : scene.triangulation.active_cell_iterators())
    if (i++ % 10 == 0)
      {
        points.push_back(cell->center());
        points.push_back(0.1 * cell->vertex(0) + 0.3 * cell->vertex(1) +
                         0.6 * cell->vertex(3));
      }
  const PointEvaluation evaluation(scene.triangulation, points);

  for (const auto &[law, solver] :
       std::vector<std::pair<std::string, std::string>>{{"neo-hooke", "direct"},
                                                        {"neo-hooke", "cg amg"},
                                                        {"linear", "direct"}})
    {
      Models::NonlinearFEM model;
      model.set_options(law, solver, 1., 2);
      const std::string name = law + ", " + solver;
      model.setup(scene);
      Vector<double> displacement;
      model.solve(prescribed, displacement);
      deallog << name
              << ": quadratic DoFs / P1 DoFs > 4: " << (model.n_dofs() > 4 * n)
              << std::endl;

      double vertex_error = 0.;
      for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
        for (unsigned int c = 0; c < 3; ++c)
          vertex_error = std::max(
            vertex_error,
            std::abs(displacement[scene.vertex_dofs()[v][c]] -
                     (G * scene.triangulation.get_vertices()[v])[c]));
      const auto [field_dofs, field] = model.displacement_field();
      softface_tests::check(field_dofs != nullptr,
                            name + ": the quadratic field is offered");
      const auto values    = evaluation.evaluate(*field_dofs, *field);
      const auto p1_values = evaluation.evaluate(scene.dof_handler, displacement);
      double     point_error = 0., p1_error = 0.;
      for (unsigned int p = 0; p < points.size(); ++p)
        {
          point_error =
            std::max(point_error, (values[p] - G * points[p]).norm());
          p1_error = std::max(p1_error, (p1_values[p] - G * points[p]).norm());
        }
      softface_tests::check(vertex_error < 1e-8,
                            name + ": vertex values = G x to 1e-8");
      softface_tests::check(point_error < 1e-8,
                            name + ": quadratic field = G x inside cells");
      softface_tests::check(p1_error < 1e-8,
                            name + ": P1 interpolation = G x inside cells");
    }

  // A point outside the mesh is refused with its number.
  try
    {
      PointEvaluation outside(scene.triangulation, {Point<3>(-1, 5, 5)});
      softface_tests::check(false, "a point outside the mesh is refused");
    }
  catch (const softface::Error &e)
    {
      deallog << e.what() << std::endl;
    }
}

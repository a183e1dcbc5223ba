// The pieces of the accuracy benchmark's reference ('reference fem'):
// 1. forces and tangent by quadrature (Elasticity::assemble) on the P1
//    layout equal the closed-form P1 ones of 'nonlinear fem' to 1e-12 (all
//    three laws, distorted mesh, strains of several percent), and so does a
//    whole solve of 'reference fem' with 'Polynomial degree = 1';
// 2. a homogeneous deformation u = G x prescribed on every join point is an
//    equilibrium of every hyperelastic law, and lies in the quadratic space:
//    the degree-2 model must return it to 1e-12 at the vertices and, through
//    PointEvaluation of its quadratic field, at points inside the cells
//    (Neo-Hooke with direct and cg amg, the linear law with direct); the
//    P1 field interpolated there must too.

#include <deal.II/base/quadrature_lib.h>

#include <softface/core/error.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/point_evaluation.h>
#include <softface/models/nonlinear_fem.h>
#include <softface/models/reference_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(quadratic_reference)
{
  Scene scene;
  softface_tests::make_distorted_cube_scene(scene, 400, true);
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
      Elasticity::assemble(MaterialLaw::from_name(law),
                           {scene.material.lame()},
                           {},
                           scene.mapping,
                           scene.dof_handler,
                           QGaussSimplex<3>(1),
                           u,
                           f_quadrature,
                           &quadrature);
      f_quadrature -= f_closed;
      quadrature.add(-1., closed);
      softface_tests::print(law + ": |f|", f_closed.l2_norm(), 4);
      softface_tests::check_below(law + ": |f_quadrature - f_closed| / |f|",
                                  f_quadrature.l2_norm() / f_closed.l2_norm(),
                                  1e-12);
      softface_tests::check_below(law + ": |K_quadrature - K_closed| / |K| "
                                        "(Frobenius)",
                                  quadrature.frobenius_norm() /
                                    closed.frobenius_norm(),
                                  1e-12);
    }
  {
    const Vector<double> lift =
      softface_tests::move_bone(scene, Point<3>(1, 0, 6), 10.);
    Models::NonlinearFEM closed;
    Models::ReferenceFEM quadrature;
    closed.set_options("neo-hooke", "direct");
    quadrature.set_options("neo-hooke", "direct");
    quadrature.set_degree(1);
    Vector<double> u_closed, u_quadrature;
    closed.setup(scene);
    closed.solve(lift, u_closed);
    quadrature.setup(scene);
    quadrature.solve(lift, u_quadrature);
    softface_tests::check_equal("reference fem, degree 1: DoFs",
                                quadrature.n_dofs(),
                                n);
    softface_tests::check_below(
      "reference fem, degree 1 vs nonlinear fem: relative difference",
      softface_tests::relative_difference(u_quadrature, u_closed),
      1e-12);
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
      Models::ReferenceFEM model;
      model.set_options(law, solver);
      const std::string name = law + ", " + solver;
      model.setup(scene);
      Vector<double> displacement;
      model.solve(prescribed, displacement);
      softface_tests::print(name + ": quadratic DoFs / P1 DoFs",
                            double(model.n_dofs()) / n,
                            4);

      double vertex_error = 0.;
      for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
        for (unsigned int c = 0; c < 3; ++c)
          vertex_error =
            std::max(vertex_error,
                     std::abs(displacement[scene.vertex_dofs()[v][c]] -
                              (G * scene.triangulation.get_vertices()[v])[c]));
      const auto [field_dofs, field] = model.displacement_field();
      softface_tests::check_equal(name + ": the quadratic field is offered",
                                  field_dofs != nullptr,
                                  1);
      const auto values = evaluation.evaluate(*field_dofs, *field);
      const auto p1_values =
        evaluation.evaluate(scene.dof_handler, displacement);
      double point_error = 0., p1_error = 0.;
      for (unsigned int p = 0; p < points.size(); ++p)
        {
          point_error =
            std::max(point_error, (values[p] - G * points[p]).norm());
          p1_error = std::max(p1_error, (p1_values[p] - G * points[p]).norm());
        }
      softface_tests::check_below(name + ": vertex values: max |u - G x|",
                                  vertex_error,
                                  1e-12);
      softface_tests::check_below(name +
                                    ": quadratic field inside cells: max |u "
                                    "- G x|",
                                  point_error,
                                  1e-12);
      softface_tests::check_below(name + ": P1 interpolation inside cells: max "
                                         "|u - G x|",
                                  p1_error,
                                  1e-12);
    }

  // A point outside the mesh is refused with its number.
  std::string message;
  try
    {
      PointEvaluation outside(scene.triangulation, {Point<3>(-1, 5, 5)});
    }
  catch (const softface::Error &e)
    {
      message = e.what();
    }
  deallog << "a point outside the mesh: " << message << std::endl;
  softface_tests::check_equal("a point outside the mesh is refused",
                              !message.empty(),
                              1);
}

// The consistent tangent of the nonlinear FEM model against a central
// finite difference of its internal forces, (f(u + e d) - f(u - e d)) / 2e,
// on a distorted mesh at a large, non-symmetric displacement (strains of
// several percent), for all three material laws: relative 1e-6.

#include <softface/models/nonlinear_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(nonlinear_tangent_check)
{
  Scene scene;
  softface_tests::make_distorted_cube_scene(scene, 400, false);

  const unsigned int n = scene.dof_handler.n_dofs();
  Vector<double>     u(n), direction(n);
  for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
    {
      const Point<3> &x = scene.triangulation.get_vertices()[v];
      for (unsigned int c = 0; c < 3; ++c)
        {
          u[scene.vertex_dofs()[v][c]] =
            1.5 * std::sin(0.05 * x[0] + c) * std::cos(0.07 * x[1] - 0.3 * c) +
            0.02 * x[(c + 1) % 3];
          direction[scene.vertex_dofs()[v][c]] =
            std::cos(0.11 * x[2] + 2. * c) * std::sin(0.03 * x[0] * (c + 1));
        }
    }

  for (const std::string law : {"st venant-kirchhoff", "neo-hooke", "linear"})
    {
      Models::NonlinearFEM model;
      model.set_options(law, "direct");
      model.setup(scene);
      SparseMatrix<double> tangent(model.sparsity_pattern());
      Vector<double>       forces, plus, minus;
      softface_tests::check_equal(law + ": u accepted (no inverted "
                                        "tetrahedron)",
                                  model.evaluate(u, forces, &tangent),
                                  1);
      const double   eps = 1e-6;
      Vector<double> up = u, um = u;
      up.add(eps, direction);
      um.add(-eps, direction);
      model.evaluate(up, plus, nullptr);
      model.evaluate(um, minus, nullptr);
      Vector<double> finite_difference = plus;
      finite_difference -= minus;
      finite_difference /= 2. * eps;
      Vector<double> K_d(n);
      tangent.vmult(K_d, direction);
      Vector<double> error = K_d;
      error -= finite_difference;
      softface_tests::print(law + ": |K d|", K_d.l2_norm(), 4);
      softface_tests::check_below(law + ": |K d - finite difference| / |K d|",
                                  error.l2_norm() / K_d.l2_norm(),
                                  1e-6,
                                  1);
    }
}

// Manufactured solution on the unit cube: u = phi(x) a + B x with
// phi = sin(pi x) sin(pi y) sin(pi z). The body force f = -div sigma(u) is
// integrated against the P1 shape functions (FEValues, QGaussSimplex) and
// applied as nodal forces; the boundary vertices get u exactly. For P1 the L2
// error must fall as h^2: the rate between the two finest meshes must lie in
// [1.8, 2.2].

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/vector_tools.h>

#include <softface/models/linear_fem.h>

#include "scenes.h"
#include "tests.h"
#include "textbook.h"

using namespace softface;

namespace
{
  const Tensor<1, 3> a = Point<3>(1., 0.5, -0.25);

  Tensor<2, 3>
  B()
  {
    Tensor<2, 3> b;
    b[0][0] = 0.1, b[0][1] = 0.02, b[1][1] = -0.05, b[1][2] = 0.03,
    b[2][0] = 0.01, b[2][2] = 0.08;
    return b;
  }

  class ExactDisplacement : public Function<3>
  {
  public:
    ExactDisplacement()
        : Function<3>(3)
    {}
    double
    value(const Point<3> &x, const unsigned int c) const override
    {
      const double phi =
        std::sin(M_PI * x[0]) * std::sin(M_PI * x[1]) * std::sin(M_PI * x[2]);
      return phi * a[c] + (B() * x)[c];
    }
  };

  // f = -(lambda + mu) grad(div u) - mu laplace(u); the affine part drops out.
  Tensor<1, 3>
  body_force(const Point<3> &x, const double lambda, const double mu)
  {
    const double s[3] = {std::sin(M_PI * x[0]),
                         std::sin(M_PI * x[1]),
                         std::sin(M_PI * x[2])};
    const double c[3] = {std::cos(M_PI * x[0]),
                         std::cos(M_PI * x[1]),
                         std::cos(M_PI * x[2])};
    const double phi  = s[0] * s[1] * s[2];
    Tensor<2, 3> hessian;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        {
          if (i == j)
            hessian[i][j] = -M_PI * M_PI * phi;
          else
            {
              const unsigned int k = 3 - i - j;
              hessian[i][j]        = M_PI * M_PI * c[i] * c[j] * s[k];
            }
        }
    return -(lambda + mu) * (hessian * a) + 3. * M_PI * M_PI * mu * phi * a;
  }
} // namespace

SOFTFACE_TEST(manufactured_solution)
{
  std::vector<double> errors, sizes;
  for (const unsigned int boxes : {4u, 8u, 16u, 32u})
    {
      Scene                scene;
      Mesh::CubeParameters cube;
      cube.edge_length         = 1.;
      cube.inner_size          = 0.5;
      cube.target_n_tetrahedra = 6 * boxes * boxes * boxes;
      Mesh::generate_cube(cube, scene.triangulation);
      scene.segments = {{"boundary", {}, {Mesh::cube_outer_face}, {}}};
      scene.material.youngs_modulus_pa = 1e6; // E = 1 N/mm^2
      scene.material.poissons_ratio    = 0.3;
      scene.setup();
      // From the textbook, not from the code under test: a wrong Lame
      // coefficient in the model then leaves the exact solution behind.
      const auto   lame   = softface_tests::textbook_lame(1., 0.3);
      const double lambda = lame.lambda, mu = lame.mu;

      Vector<double>                       forces(scene.dof_handler.n_dofs());
      const QGaussSimplex<3>               quadrature(4);
      FEValues<3>                          fe_values(scene.mapping,
                            scene.fe,
                            quadrature,
                            update_values | update_quadrature_points |
                              update_JxW_values);
      std::vector<types::global_dof_index> dofs(scene.fe.n_dofs_per_cell());
      for (const auto &cell : scene.dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          cell->get_dof_indices(dofs);
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              const Tensor<1, 3> f =
                body_force(fe_values.quadrature_point(q), lambda, mu);
              for (unsigned int i = 0; i < dofs.size(); ++i)
                {
                  const unsigned int c =
                    scene.fe.system_to_component_index(i).first;
                  forces[dofs[i]] +=
                    f[c] * fe_values.shape_value(i, q) * fe_values.JxW(q);
                }
            }
        }

      Vector<double> prescribed(scene.dof_handler.n_dofs());
      VectorTools::interpolate(scene.mapping,
                               scene.dof_handler,
                               ExactDisplacement(),
                               prescribed);

      Models::LinearFEM model;
      model.set_solver("cg amg", 1e-12);
      model.set_nodal_forces(forces);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);

      Vector<double> cellwise(scene.triangulation.n_active_cells());
      VectorTools::integrate_difference(scene.mapping,
                                        scene.dof_handler,
                                        u,
                                        ExactDisplacement(),
                                        cellwise,
                                        QGaussSimplex<3>(4),
                                        VectorTools::L2_norm);
      errors.push_back(VectorTools::compute_global_error(scene.triangulation,
                                                         cellwise,
                                                         VectorTools::L2_norm));
      sizes.push_back(1. / boxes);
      deallog << "h = 1/" << boxes << ": L2 error "
              << softface_tests::rounded(errors.back(), 2) << std::endl;
    }
  for (unsigned int i = 1; i < errors.size(); ++i)
    deallog << "rate "
            << softface_tests::rounded(std::log(errors[i - 1] / errors[i]) /
                                         std::log(sizes[i - 1] / sizes[i]),
                                       2)
            << std::endl;
  const double finest_rate =
    std::log(errors[errors.size() - 2] / errors.back()) / std::log(2.);
  softface_tests::check_below("|rate on the finest meshes - 2|",
                              std::abs(finest_rate - 2.),
                              0.2);
}

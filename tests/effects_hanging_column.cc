// Gravity against the closed form: a block of tissue (80 mm, Poisson's ratio
// 0) hanging from its top face z = L under its own weight. The exact answer
// is one-dimensional: u_z(z) = -rho g (L^2 - z^2) / (2 E), the bottom
// sagging by rho g L^2 / (2 E) (10.46 mm for water's density and 3 kPa).
// It is quadratic, so P1 elements approach it at second order in the mesh
// size (the largest pointwise error does so from below). The converged mass
// tensor model solves the same equations as linear FEM; quadratic elements
// (the reference model with the linear law) hold it exactly; the nonlinear FEM
// must approach linear FEM as the load goes to zero (its difference falling
// with the load); the mass spring model sags the right way by about the
// right amount, and its answer is in equilibrium with the weight computed
// here (the top holds all of it, every free point is in balance). Without
// the effect nothing moves.

#include <softface/core/displacement.h>
#include <softface/models/linear_fem.h>
#include <softface/models/mass_spring.h>
#include <softface/models/mass_tensor.h>
#include <softface/models/nonlinear_fem.h>
#include <softface/models/reference_fem.h>

#include "effects.h"
#include "tests.h"

using namespace softface;

namespace
{
  constexpr double L = 80., E = 3000., rho = 1000.; // mm, Pa, kg/m^3

  void
  make_column(Scene &scene, const unsigned int n_tetrahedra)
  {
    softface_tests::make_block(scene, n_tetrahedra, 1);
    scene.material.poissons_ratio = 0.;
    scene.segments                = {{"top", {}, {12}, {}}};
    scene.setup();
  }

  void
  add_gravity(Scene &scene, const double g)
  {
    softface_tests::apply_effect(scene,
                                 "gravity",
                                 {{"Gravity", "0, 0, " + std::to_string(-g)},
                                  {"Density", std::to_string(rho)}});
  }

  // Largest distance from the closed form, relative to the bottom's sag.
  double
  relative_error(const Scene &scene, const Vector<double> &u, const double g)
  {
    const double load  = rho * g * 1e-9 / (2. * E * 1e-6); // 1/mm
    double       error = 0.;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      {
        const auto    &dofs  = scene.vertex_dofs()[v];
        const Point<3> x     = scene.triangulation.get_vertices()[v];
        const double   exact = -load * (L * L - x[2] * x[2]);
        error                = std::max({error,
                                         std::abs(u[dofs[2]] - exact),
                                         std::abs(u[dofs[0]]),
                                         std::abs(u[dofs[1]])});
      }
    return error / (load * L * L);
  }

  Vector<double>
  solve_linear(const Scene &scene)
  {
    Models::LinearFEM fem;
    fem.set_solver("direct", 0.);
    fem.setup(scene);
    Vector<double> u;
    fem.solve(Vector<double>(scene.dof_handler.n_dofs()), u);
    return u;
  }
} // namespace

SOFTFACE_TEST(effects_hanging_column)
{
  const double g = 9.81;
  softface_tests::print("closed form: bottom sag (mm)",
                        rho * g * 1e-9 * L * L / (2. * E * 1e-6),
                        5);

  // Off: no load, nothing moves.
  Scene          scene;
  Vector<double> u;
  make_column(scene, 3000);
  const Vector<double> no_motion(scene.dof_handler.n_dofs());
  softface_tests::check_below("off: linear fem, max |u| (mm)",
                              solve_linear(scene).linfty_norm(),
                              0.);
  {
    Models::MassSpring msm;
    msm.setup(scene);
    msm.solve(no_motion, u);
    softface_tests::check_below("off: mass spring, max |u| (mm)",
                                u.linfty_norm(),
                                0.);
  }

  // On: second-order convergence of linear FEM to the closed form.
  add_gravity(scene, g);
  const Vector<double> u_coarse = solve_linear(scene);
  const double         coarse   = relative_error(scene, u_coarse, g);
  Scene                fine_scene;
  make_column(fine_scene, 24000);
  add_gravity(fine_scene, g);
  const double fine = relative_error(fine_scene, solve_linear(fine_scene), g);
  // Mesh size from the number of cells (six per grid box).
  const auto h = [](const Scene &s) {
    return L / std::cbrt(s.triangulation.n_active_cells() / 6.);
  };
  softface_tests::print("on: linear fem, relative error, coarse mesh", coarse);
  softface_tests::check_below("on: linear fem, relative error, fine mesh",
                              fine,
                              0.02);
  // Still pre-asymptotic in the largest pointwise error: 1.54 from 3k to
  // 25k cells, 1.68 from 25k to 64k, approaching 2.
  softface_tests::check_within("on: order of convergence (2)",
                               std::log(coarse / fine) /
                                 std::log(h(scene) / h(fine_scene)),
                               1.4,
                               2.3);

  // Quadratic elements hold the quadratic closed form: the body force
  // integrated on the reference's own layout.
  {
    Models::ReferenceFEM reference;
    reference.set_options("linear", "direct");
    reference.set_degree(2);
    reference.setup(scene);
    reference.solve(no_motion, u);
    softface_tests::check_below(
      "on: reference fem (P2, linear law), relative error",
      relative_error(scene, u, g),
      1e-12);
  }

  // The mass tensor model's converged answer is linear FEM's.
  {
    Models::MassTensor mtm;
    mtm.set_scheme(/*gauss_seidel=*/true, /*threshold=*/0., 10, true);
    mtm.set_relaxation(1.8); // SOR: the soft column converges slowly
    mtm.setup(scene);
    mtm.solve(no_motion, u);
    Vector<double> difference = u;
    difference -= u_coarse;
    softface_tests::check_below("on: max |u_MTM - u_linear fem| (mm)",
                                difference.linfty_norm(),
                                1e-6);
  }

  // Nonlinear FEM tends to linear FEM as the load goes to zero.
  std::vector<double> differences;
  for (const double factor : {0.1, 0.01})
    {
      Scene loaded;
      make_column(loaded, 3000);
      add_gravity(loaded, g * factor);
      const Vector<double> linear = solve_linear(loaded);
      Models::NonlinearFEM nonlinear;
      nonlinear.set_options("neo-hooke", "direct");
      nonlinear.setup(loaded);
      nonlinear.solve(no_motion, u);
      u -= linear;
      differences.push_back(u.linfty_norm() / linear.linfty_norm());
      softface_tests::print("on, g x " + softface_tests::rounded(factor) +
                              ": max |u_nonlinear - u_linear| / max |u_linear|",
                            differences.back(),
                            2);
    }
  softface_tests::check_below("on, g x 0.01: relative difference",
                              differences[1],
                              0.01);
  softface_tests::check_within(
    "on: difference at g x 0.1 / at g x 0.01 (first order: 10)",
    differences[0] / differences[1],
    7.,
    13.);

  // The mass spring model: springs, not elasticity; the sag's size only.
  {
    Models::MassSpring msm;
    msm.setup(scene);
    msm.solve(no_motion, u);
    double bottom = 0.;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      bottom = std::min(bottom, u[scene.vertex_dofs()[v][2]]);
    softface_tests::print(
      "on: mass spring, lowest z displacement / closed-form sag",
      -bottom / (rho * g * 1e-9 * L * L / (2. * E * 1e-6)));
    softface_tests::check_within(
      "on: mass spring, lowest z displacement / closed-form sag",
      -bottom / (rho * g * 1e-9 * L * L / (2. * E * 1e-6)),
      0.3,
      3.);

    // Its equilibrium, computed here: the springs' forces (Mollemans et al.
    // 2007, eq. 4, on the constants mass_spring_constants checks by hand) at
    // the deformed positions against the weight, rho g V / 4 of each
    // tetrahedron at each of its vertices (the consistent load of a constant
    // body force on P1). The top holds the whole weight, and every free point
    // is in balance, to within the model's stop (no step over 0.001 mm: 2 to
    // 3 % of the weight here; a load counted twice would leave 100 %).
    // The model's points are the DoF triples 3p, 3p + 1, 3p + 2.
    const auto               &vertices = scene.triangulation.get_vertices();
    std::vector<Point<3>>     x(vertices.size());
    std::vector<Tensor<1, 3>> force(vertices.size());
    const auto                point = [&](const unsigned int v) {
      return scene.vertex_dofs()[v][0] / 3;
    };
    for (unsigned int v = 0; v < vertices.size(); ++v)
      for (unsigned int d = 0; d < 3; ++d)
        x[point(v)][d] = vertices[v][d] + u[3 * point(v) + d];
    double weight = 0.;
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      {
        const double w = rho * 1e-9 * cell->measure() * g; // N
        weight += w;
        for (const unsigned int v : cell->vertex_indices())
          force[point(cell->vertex_index(v))][2] -= w / 4.;
      }
    for (const auto &spring : msm.springs())
      {
        const Tensor<1, 3> ab = x[spring.b] - x[spring.a];
        const Tensor<1, 3> f =
          spring.stiffness * (ab.norm() - spring.rest_length) / ab.norm() * ab;
        force[spring.a] += f;
        force[spring.b] -= f;
      }
    double held = 0., unbalanced = 0.;
    for (unsigned int p = 0; p < vertices.size(); ++p)
      if (scene.join_dofs()[3 * p + 2])
        held -= force[p][2];
      else
        unbalanced += force[p].norm();
    softface_tests::print("on: mass spring, weight (N)", weight, 6);
    softface_tests::check_below(
      "on: mass spring, |weight held by the top - weight| / weight",
      std::abs(held - weight) / weight,
      0.05,
      3);
    softface_tests::check_below(
      "on: mass spring, sum of |unbalanced force| at free points / weight",
      unbalanced / weight,
      0.05,
      3);
  }
}

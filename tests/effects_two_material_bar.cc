// Heterogeneous tissue against the closed form: a block of two tissues in
// series (x < 40 mm: E1, beyond: E2 = 4 E1, Poisson's ratio 0), its face
// x = 0 held and its face x = 80 pulled by delta along x. The exact answer
// is one-dimensional and piecewise linear, u_x = sigma x / E1 up to the
// interface, with one stress sigma = delta / (L1/E1 + L2/E2) in both
// tissues; P1 elements on a mesh whose grid plane is the interface hold it
// exactly. Linear FEM and the converged mass tensor model must reproduce it
// to the solver's tolerance, with the effect on and, giving the homogeneous
// answer u_x = delta x / L, off. The nonlinear FEM approaches it for a small
// pull; the mass spring model (springs, not elasticity) only roughly. Each
// tissue's own Poisson's ratio: the right tissue alone deforming gives the
// answer of homogeneous tissue with its Poisson's ratio.

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
  constexpr double L = 80., E1 = 3000., E2 = 12000.; // mm, Pa

  // Largest distance of a displacement from u = (f(x), 0, 0) at the
  // vertices.
  template <typename Exact>
  double
  max_error(const Scene &scene, const Vector<double> &u, const Exact &exact)
  {
    double error = 0.;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      {
        const auto    &dofs = scene.vertex_dofs()[v];
        const Point<3> x    = scene.triangulation.get_vertices()[v];
        error               = std::max({error,
                                        std::abs(u[dofs[0]] - exact(x[0])),
                                        std::abs(u[dofs[1]]),
                                        std::abs(u[dofs[2]])});
      }
    return error;
  }

  // The x displacement of the vertices on the interface x = L/2 (mean).
  double
  interface_displacement(const Scene &scene, const Vector<double> &u)
  {
    double       sum = 0.;
    unsigned int n   = 0;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      if (std::abs(scene.triangulation.get_vertices()[v][0] - L / 2.) < 1e-9)
        {
          sum += u[scene.vertex_dofs()[v][0]];
          ++n;
        }
    return sum / n;
  }

  Vector<double>
  pull(const Scene &scene, const double delta)
  {
    Vector<double> prescribed(scene.dof_handler.n_dofs());
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      if (scene.vertex_segment()[v] == 1)
        prescribed[scene.vertex_dofs()[v][0]] = delta;
    return prescribed;
  }
} // namespace

SOFTFACE_TEST(effects_two_material_bar)
{
  Scene scene;
  softface_tests::make_block(scene, 3000, 3);
  scene.material.poissons_ratio = 0.;
  scene.segments = {{"left", {}, {10}, {}}, {"right", {}, {11}, {}}};
  scene.setup();

  const double delta = 0.8;
  const double sigma = delta / ((L / 2.) / E1 + (L / 2.) / E2); // Pa
  const auto   exact = [&](const double x) {
    return x <= L / 2. ? sigma * x / E1 :
                           sigma * (L / 2.) / E1 + sigma * (x - L / 2.) / E2;
  };
  const auto homogeneous = [&](const double x) { return delta * x / L; };
  const Vector<double> prescribed = pull(scene, delta);

  const auto solve_linear = [&]() {
    Models::LinearFEM fem;
    fem.set_solver("direct", 0.);
    fem.setup(scene);
    Vector<double> u;
    fem.solve(prescribed, u);
    return u;
  };
  const auto solve_mtm = [&]() {
    Models::MassTensor mtm;
    mtm.set_scheme(/*gauss_seidel=*/true, /*threshold=*/0., 10, true);
    mtm.setup(scene);
    Vector<double> u;
    mtm.solve(prescribed, u);
    return u;
  };

  // Off: one tissue.
  softface_tests::check_below("off: linear fem, max error (mm)",
                              max_error(scene, solve_linear(), homogeneous),
                              1e-12);
  softface_tests::check_below("off: mass tensor, max error (mm)",
                              max_error(scene, solve_mtm(), homogeneous),
                              1e-6);

  // On: E1 left, E2 right, both with Poisson's ratio 0.
  softface_tests::apply_effect(scene,
                               "heterogeneous tissue",
                               {{"Young's moduli", "1: 3000, 3: 12000"},
                                {"Poisson's ratios", "1: 0, 3: 0"}});
  softface_tests::print("closed form: interface displacement (mm)",
                        exact(L / 2.),
                        6);
  softface_tests::print("closed form: stress (Pa)", sigma, 6);

  const Vector<double> u_fem = solve_linear();
  softface_tests::check_below("on: linear fem, max error (mm)",
                              max_error(scene, u_fem, exact),
                              1e-12);
  const double u_interface = interface_displacement(scene, u_fem);
  softface_tests::check_below("on: linear fem, stress left / closed form - 1",
                              std::abs(E1 * u_interface / (L / 2.) / sigma -
                                       1.),
                              1e-12);
  softface_tests::check_below(
    "on: linear fem, stress right / closed form - 1",
    std::abs(E2 * (delta - u_interface) / (L / 2.) / sigma - 1.),
    1e-12);
  softface_tests::check_below("on: mass tensor, max error (mm)",
                              max_error(scene, solve_mtm(), exact),
                              1e-6);
  {
    // The quadratic reference with the linear law, tissues by quadrature.
    Models::ReferenceFEM reference;
    reference.set_options("linear", "direct");
    reference.set_degree(2);
    reference.setup(scene);
    Vector<double> u;
    reference.solve(prescribed, u);
    softface_tests::check_below(
      "on: reference fem (P2, linear law), max error (mm)",
      max_error(scene, u, exact),
      1e-12);
  }

  // A pull of a tenth of a per cent: the large-deformation laws differ from
  // the linear one by about the strain.
  {
    const double         small = 0.08;
    Models::NonlinearFEM nonlinear;
    nonlinear.set_options("neo-hooke", "direct");
    nonlinear.setup(scene);
    Vector<double> u;
    nonlinear.solve(pull(scene, small), u);
    softface_tests::check_below(
      "on, pull 0.08 mm: nonlinear fem interface displacement / closed form "
      "- 1",
      std::abs(interface_displacement(scene, u) /
                 (exact(L / 2.) * small / delta) -
               1.),
      2e-3);
  }
  {
    Models::MassSpring msm;
    msm.setup(scene);
    Vector<double> u;
    msm.solve(prescribed, u);
    softface_tests::check_within(
      "on: mass spring interface displacement / closed form",
      interface_displacement(scene, u) / exact(L / 2.),
      0.9,
      1.1);
  }

  // Each tissue's own Poisson's ratio. The left tissue held whole (every
  // vertex of its cells a join point) leaves the right one alone to deform:
  // pulled along x, its sides contract by its Poisson's ratio 0.3, and
  // under displacement loading its modulus does not matter. The effect's
  // answer (tissues 0.1 and 0.3, Material's 0.46 unused) must then be the
  // answer of homogeneous tissue with Material/Poisson's ratio = 0.3, which
  // reaches the model by another path.
  const auto held_left = [&](Scene &s) {
    softface_tests::make_block(s, 3000, 3);
    s.segments = {{"held", {1}, {}, {}}, {"right", {}, {11}, {}}};
  };
  Scene two_tissues, one_tissue;
  held_left(two_tissues);
  two_tissues.material.poissons_ratio = 0.46;
  two_tissues.setup();
  softface_tests::apply_effect(two_tissues,
                               "heterogeneous tissue",
                               {{"Young's moduli", "1: 3000, 3: 12000"},
                                {"Poisson's ratios", "1: 0.1, 3: 0.3"}});
  held_left(one_tissue);
  one_tissue.material.poissons_ratio = 0.3;
  one_tissue.setup();
  Vector<double> u_two, u_one;
  for (auto [s, u] : {std::make_pair(&two_tissues, &u_two),
                      std::make_pair(&one_tissue, &u_one)})
    {
      Models::LinearFEM fem;
      fem.set_solver("direct", 0.);
      fem.setup(*s);
      fem.solve(pull(*s, 4.), *u);
    }
  softface_tests::print("right tissue held on the left, pulled 4 mm: max |u| "
                        "(mm)",
                        u_one.linfty_norm(),
                        6);
  u_two -= u_one;
  softface_tests::check_below(
    "two tissues (nu 0.1, 0.3) - one tissue (nu 0.3), max |difference| (mm)",
    u_two.linfty_norm(),
    1e-12);
}

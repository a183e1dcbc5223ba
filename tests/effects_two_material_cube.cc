// Heterogeneous tissue in all four models on the cube of Mollemans et al. 2007:
// the tissue above the mid-plane four times as stiff as below, the inner cube
// moved 6 mm up. The converged mass tensor model solves linear FEM's equations
// (to 1e-6 mm); the effect with one modulus everywhere gives exactly the
// answer without it, in every model; under displacement loading only the
// ratio of the moduli matters (both scaled by 10: the same answer).

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/models/linear_fem.h>
#include <softface/models/mass_spring.h>
#include <softface/models/mass_tensor.h>
#include <softface/models/nonlinear_fem.h>

#include "effects.h"
#include "scenes.h"
#include "tests.h"

#include <functional>
#include <memory>

using namespace softface;

namespace
{
  Vector<double>
  run(Models::Interface &model, const Scene &scene, const Vector<double> &d)
  {
    model.setup(scene);
    Vector<double> u;
    model.solve(d, u);
    return u;
  }

  double
  max_difference(Vector<double> a, const Vector<double> &b)
  {
    a -= b;
    return a.linfty_norm();
  }

  // Mean |u| of the free vertices above (upper) or below the mid-plane.
  double
  mean_motion(const Scene &scene, const Vector<double> &u, const bool upper)
  {
    double       sum = 0.;
    unsigned int n   = 0;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      if (scene.vertex_segment()[v] >= scene.segments.size() &&
          (scene.triangulation.get_vertices()[v][2] > 40.) == upper)
        {
          const auto &d = scene.vertex_dofs()[v];
          sum += std::sqrt(u[d[0]] * u[d[0]] + u[d[1]] * u[d[1]] +
                           u[d[2]] * u[d[2]]);
          ++n;
        }
    return sum / n;
  }
} // namespace

SOFTFACE_TEST(effects_two_material_cube)
{
  const auto make = [](Scene &scene) {
    softface_tests::make_cube_scene(scene, 3000, 3);
  };
  Scene plain, same, stiffer, scaled;
  make(plain);
  make(same);
  make(stiffer);
  make(scaled);
  softface_tests::apply_effect(same,
                               "heterogeneous tissue",
                               {{"Young's moduli", "1: 3000, 3: 3000"}});
  softface_tests::apply_effect(stiffer,
                               "heterogeneous tissue",
                               {{"Young's moduli", "1: 3000, 3: 12000"},
                                {"Poisson's ratios", "1: 0.46, 3: 0.4"}});
  softface_tests::apply_effect(scaled,
                               "heterogeneous tissue",
                               {{"Young's moduli", "1: 30000, 3: 120000"},
                                {"Poisson's ratios", "1: 0.46, 3: 0.4"}});
  const Vector<double> d = softface_tests::move_bone(plain, Point<3>(0, 0, 6));

  const std::vector<
    std::pair<std::string, std::function<std::unique_ptr<Models::Interface>()>>>
    models = {{"linear fem",
               []() {
                 auto m = std::make_unique<Models::LinearFEM>();
                 m->set_solver("direct", 0.);
                 return m;
               }},
              {"mass tensor",
               []() {
                 auto m = std::make_unique<Models::MassTensor>();
                 m->set_scheme(true, 0., 10, true);
                 return m;
               }},
              {"mass spring",
               []() { return std::make_unique<Models::MassSpring>(); }},
              {"nonlinear fem", []() {
                 auto m = std::make_unique<Models::NonlinearFEM>();
                 m->set_options("neo-hooke", "direct");
                 return m;
               }}};

  Vector<double> linear_fem;
  for (const auto &[name, create] : models)
    {
      const Vector<double> u_plain   = run(*create(), plain, d);
      const Vector<double> u_same    = run(*create(), same, d);
      const Vector<double> u_stiffer = run(*create(), stiffer, d);
      const Vector<double> u_scaled  = run(*create(), scaled, d);
      softface_tests::check_below(name +
                                    ": one modulus in both tissues, max |u - "
                                    "u without the effect| (mm)",
                                  max_difference(u_same, u_plain),
                                  1e-12);
      softface_tests::check_below(
        name + ": both moduli x 10, max |u - u unscaled| (mm)",
        max_difference(u_scaled, u_stiffer),
        name == "mass spring" ? 1e-11 : 1e-12);
      softface_tests::print(name + ": max |u - u homogeneous| (mm)",
                            max_difference(u_stiffer, u_plain),
                            2);
      softface_tests::print(
        name + ": mean motion of the free vertices, upper / lower half, "
               "homogeneous",
        mean_motion(plain, u_plain, true) / mean_motion(plain, u_plain, false),
        2);
      softface_tests::print(name + ": mean motion, upper / lower half, stiffer "
                                   "upper half",
                            mean_motion(stiffer, u_stiffer, true) /
                              mean_motion(stiffer, u_stiffer, false),
                            2);
      if (name == "linear fem")
        linear_fem = u_stiffer;
      if (name == "mass tensor")
        softface_tests::check_below("mass tensor: max |u - u_linear fem| (mm)",
                                    max_difference(u_stiffer, linear_fem),
                                    1e-6);
    }
}

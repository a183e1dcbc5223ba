// With homogeneous tissue and only prescribed displacements, the answer does
// not depend on Young's modulus (Mollemans et al. 2007, Sec. 3.4), for every
// registered model with its default parameters, while it does depend on
// Poisson's ratio (so the comparison can tell a wrong material apart). Also at
// both ends of the range softface accepts (1e-3 and 1e13 Pa): far below it
// forces underflow (at 1e-200 Pa a nonlinear solve can return u = 0 as
// "converged" and CG's residual become NaN).

#include <softface/models/interface.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  Vector<double>
  solve(const std::string &model_name,
        const double       youngs_modulus_pa,
        const double       poissons_ratio)
  {
    Scene scene;
    scene.material.youngs_modulus_pa = youngs_modulus_pa;
    scene.material.poissons_ratio    = poissons_ratio;
    softface_tests::make_cube_scene(scene, 5000);
    ParameterHandler prm;
    Models::declare_parameters(prm);
    const auto model = Models::create(model_name, prm);
    model->setup(scene);
    Vector<double> u;
    model->solve(softface_tests::move_bone(scene, Point<3>(0, 0, 6), 5.), u);
    return u;
  }
} // namespace

SOFTFACE_TEST(youngs_modulus_independence)
{
  for (const std::string &name : Models::registered_names())
    {
      const Vector<double> soft  = solve(name, 3000., 0.46);
      const Vector<double> stiff = solve(name, 3e6, 0.46);
      softface_tests::check_below(name + ": E = 3 kPa vs 3 MPa: relative "
                                         "difference",
                                  softface_tests::relative_difference(stiff,
                                                                      soft),
                                  1e-8);
      // The ends of the accepted range (Material::min/max_youngs_modulus_pa).
      for (const double E :
           {Material::min_youngs_modulus_pa, Material::max_youngs_modulus_pa})
        softface_tests::check_below(
          name + ": E = 3 kPa vs " + softface_tests::rounded(E) +
            " Pa: relative difference",
          softface_tests::relative_difference(solve(name, E, 0.46), soft),
          1e-8);
    }
  const Vector<double> soft  = solve("linear fem", 3000., 0.46);
  const Vector<double> other = solve("linear fem", 3000., 0.30);
  softface_tests::check_above(
    "linear fem: Poisson's ratio 0.30 vs 0.46: relative difference",
    softface_tests::relative_difference(other, soft),
    1e-3);
}

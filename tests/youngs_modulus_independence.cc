// With homogeneous tissue and only prescribed displacements, the answer does
// not depend on Young's modulus (seed 3.4), while it does depend on Poisson's
// ratio (so the comparison can tell a wrong material apart).

#include <softface/models/linear_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  Vector<double>
  solve(const double youngs_modulus_pa, const double poissons_ratio)
  {
    Scene scene;
    scene.material.youngs_modulus_pa = youngs_modulus_pa;
    scene.material.poissons_ratio    = poissons_ratio;
    softface_tests::make_cube_scene(scene, 5000);
    Models::LinearFEM model;
    model.set_solver("direct", 0.);
    model.setup(scene);
    Vector<double> u;
    model.solve(softface_tests::move_bone(scene, Point<3>(0, 0, 6), 5.), u);
    return u;
  }
} // namespace

SOFTFACE_TEST(youngs_modulus_independence)
{
  const Vector<double> soft  = solve(3000., 0.46);
  const Vector<double> stiff = solve(3e6, 0.46);
  const Vector<double> other = solve(3000., 0.30);
  softface_tests::check(softface_tests::relative_difference(stiff, soft) <
                          1e-10,
                        "E = 3 kPa and E = 3 MPa give the same displacement");
  softface_tests::check(softface_tests::relative_difference(other, soft) > 1e-3,
                        "Poisson's ratio 0.30 and 0.46 differ");
}

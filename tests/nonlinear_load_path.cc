// How the nonlinear models reach a planning.
// - The rigid load path: every fraction of a planned motion is rigid (the
//   distances between bone points are kept), the whole fraction is the
//   motion; the displacement scaled linearly is not rigid on the way (a bone
//   turned by theta shrinks by 1 - cos(theta / 2) half-way).
// - A turned bone on the cube: with Neo-Hooke every load path and predictor
//   reaches the full load, all with the same answer.
// - KINSOL as the corrector gives the answer of softface's Newton loop to
//   the Newton tolerance.

#include "nonlinear_runs.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;


SOFTFACE_TEST(nonlinear_load_path)
{
  // The rigid path, point by point.
  {
    const RigidMotion motion(Tensor<1, 3>({3., -2., 5.}),
                             Tensor<1, 3>({1., 1., 0.}),
                             30.,
                             Point<3>(40, 40, 40));
    const Point<3>    a(35, 35, 35), b(45, 45, 45);
    double            largest_change = 0., linear_change = 0.;
    for (const double s : {0.25, 0.5, 0.75})
      {
        const RigidMotion part = motion.fraction(s);
        largest_change =
          std::max(largest_change,
                   std::abs(part(a).distance(part(b)) - a.distance(b)));
        const Point<3> la = a + s * motion.displacement(a);
        const Point<3> lb = b + s * motion.displacement(b);
        linear_change =
          std::max(linear_change, std::abs(la.distance(lb) - a.distance(b)));
      }
    softface_tests::check_below(
      "rigid path: largest change of a bone distance (mm)",
      largest_change,
      1e-12);
    softface_tests::print("linear path: largest change of the same (mm)",
                          linear_change,
                          3);
    softface_tests::check_below(
      "rigid path: fraction 1 against the motion (mm)",
      (motion.fraction(1.)(a) - motion(a)).norm(),
      1e-12);
  }

  // The cube's bone turned by 30 degrees about x through the centre of the
  // cube's lower face and lifted: its points move by up to about 25 mm.
  Scene scene;
  softface_tests::make_cube_scene(scene, 4000);
  Planning planning;
  planning.set_motion(1,
                      RigidMotion(Tensor<1, 3>({0., 0., 4.}),
                                  Tensor<1, 3>({1., 0., 0.}),
                                  30.,
                                  Point<3>(40, 40, 0)));
  softface_tests::print("largest bone displacement (mm)",
                        planning.prescribed_displacement(scene).linfty_norm(),
                        3);

  std::map<std::string, softface_tests::NonlinearOutcome> outcomes;
  for (const std::string path : {"linear", "rigid"})
    for (const std::string predictor : {"join only", "tangent", "secant"})
      {
        const std::string name = "neo-hooke, " + path + ", " + predictor;
        const auto        o    = softface_tests::solve_nonlinear(
          scene, planning, "neo-hooke", path, predictor, "newton", "0.01");
        deallog << name << ": load reached " << std::setprecision(3) << o.load
                << ", cut-backs " << o.cutbacks << std::endl;
        softface_tests::check_equal(name + ": reaches the full load",
                                    o.converged,
                                    1);
        outcomes[name] = o;
      }
  // Where they both converge, every variant has the same answer.
  const Vector<double> &reference = outcomes["neo-hooke, rigid, tangent"].u;
  double                largest   = 0.;
  for (const auto &[name, o] : outcomes)
    if (o.converged)
      largest =
        std::max(largest, softface_tests::relative_difference(o.u, reference));
  softface_tests::check_below(
    "neo-hooke: variants that converge agree (relative max difference)",
    largest,
    1e-6);

  // KINSOL corrects as softface's loop does.
  {
    const auto kinsol = softface_tests::solve_nonlinear(
      scene, planning, "neo-hooke", "rigid", "tangent", "kinsol", "0.01");
    deallog << "kinsol: " << (kinsol.converged ? "converged" : kinsol.message)
            << ", " << kinsol.newton << " iterations (newton: "
            << outcomes["neo-hooke, rigid, tangent"].newton << ")" << std::endl;
    softface_tests::check_equal("kinsol: converged", kinsol.converged, 1);
    if (kinsol.converged)
      softface_tests::check_below(
        "kinsol against newton (relative max difference)",
        softface_tests::relative_difference(kinsol.u, reference),
        1e-6);
  }
}

// The mass tensor model's precision (Report precision: its distance to the
// converged answer of its equations) measured against linear FEM's answer
// to the same plan, as a run hands it over
// (Models::PlanContext::converged_answer), equals the one against its own
// direct solve: the tensors are the blocks of linear FEM's stiffness, so that
// answer is the converged one (here solved by CHOLMOD, as the model's own).

#include <softface/models/linear_fem.h>
#include <softface/models/mass_tensor.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(mass_tensor_precision_reuse)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 3000);
  const Vector<double> turn =
    softface_tests::move_bone(scene, Point<3>(2, -1, 3), 12.);

  Models::LinearFEM linear;
  linear.set_solver("direct", 1e-12);
  linear.setup(scene);
  Vector<double> linear_answer;
  linear.solve(turn, linear_answer);

  Models::MassTensor own, reused;
  own.set_report_precision(true);
  reused.set_report_precision(true);
  own.setup(scene);
  reused.setup(scene);
  Vector<double> a, b;
  own.solve(turn, a);
  reused.solve(turn, b, {Models::LoadPath(), nullptr, &linear_answer});

  std::string against;
  for (const auto &detail : reused.statistics().details)
    if (detail.name == "precision against")
      against = detail.text;
  deallog << "precision against: " << against << std::endl;
  softface_tests::check_above("precision max, own direct solve (mm)",
                              own.report().precision_max,
                              1e-5);
  softface_tests::check_below("|precision max, linear fem's answer - own| (mm)",
                              std::abs(reused.report().precision_max -
                                       own.report().precision_max),
                              1e-10);
  softface_tests::check_below(
    "|precision mean, linear fem's answer - own| (mm)",
    std::abs(reused.report().precision_mean - own.report().precision_mean),
    1e-10);
}

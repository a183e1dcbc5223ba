// Several plans per scene: a sweep and a listed plan, each model
// set up once. The report has one row per model and plan (every plan's
// largest displacement is its join points' largest motion, and each model is
// compared with linear FEM on the same plan). Run again with
// 'Response basis = always', linear FEM and the mass tensor model compute
// every plan from 12 responses per moved segment and the body force's
// answer: each plan must equal the plan's own solve to 1e-8 relative
// (exact but for the solver's rounding; a wrong basis entry, centre or sign
// shows as an error of the order of the motion).

#include "run_scene.h"

#include <fstream>
#include <sstream>

SOFTFACE_TEST(run_planning_sweep)
{
  using namespace softface;
  const std::string prm = softface_tests::source_file("run_planning_sweep.prm");
  Simulator         solved;
  softface_tests::check_equal("exit code",
                              softface_tests::run_scene(solved, prm),
                              0);
  softface_tests::check_equal("runs (3 models x 4 plans)",
                              solved.runs().size(),
                              12);

  // The same scene with the basis, from a copy of the file.
  std::ostringstream text;
  text << std::ifstream(prm).rdbuf();
  std::string       with_basis = text.str();
  const std::string never      = "set Response basis = never";
  with_basis.replace(with_basis.find(never),
                     never.size(),
                     "set Response basis = always");
  std::ofstream("run_planning_sweep_basis.prm") << with_basis;
  Simulator          combined;
  std::ostringstream out, err;
  softface_tests::check_equal("exit code with the basis",
                              combined.run("run_planning_sweep_basis.prm",
                                           out,
                                           err),
                              0);

  for (unsigned int r = 0; r < combined.runs().size(); ++r)
    {
      const auto &a        = combined.runs()[r];
      const auto &b        = solved.runs()[r];
      const bool  by_basis = a.basis_time > 0.;
      if (a.model == "nonlinear fem")
        {
          // No basis: Newton, its first step from linear FEM's combination
          // for the same plan; the same equilibrium.
          softface_tests::check_equal(a.label() + " used a basis",
                                      by_basis,
                                      false);
          bool from_guess = false;
          for (const auto &detail : a.statistics.details)
            from_guess |= detail.name == "initial guess";
          softface_tests::check_equal(a.label() + " started from the guess",
                                      from_guess,
                                      true);
          const auto linear = [](const Report::ModelRun &run) {
            for (const auto &detail : run.statistics.details)
              if (detail.name == "linear iterations")
                return detail.value;
            return -1.;
          };
          deallog << a.label() << ": Newton iterations "
                  << b.statistics.iterations << " -> "
                  << a.statistics.iterations << ", linear solves " << linear(b)
                  << " -> " << linear(a) << std::endl;
          Vector<double> difference = a.displacement;
          difference -= b.displacement;
          softface_tests::check_below(a.label() +
                                        ": |from the guess - from rest| / "
                                        "|from rest|",
                                      difference.linfty_norm() /
                                        b.displacement.linfty_norm(),
                                      1e-8);
          continue;
        }
      softface_tests::check_equal(a.label() + " used a basis", by_basis, true);
      Vector<double> difference = a.displacement;
      difference -= b.displacement;
      softface_tests::check_below(a.label() +
                                    ": |combination - solve| / |solve|",
                                  difference.linfty_norm() /
                                    b.displacement.linfty_norm(),
                                  1e-8);
    }
}

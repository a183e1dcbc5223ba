// Every registered model, with its default parameters, set up once and
// solved for three plannings in turn (a lift, a turn with a shift, the lift
// again): the second plan's answer equals a fresh model's, and the repeated
// plan gives its first answer again, so nothing of one planning leaks into
// the next. The mass spring model, whose solves start from the previous
// answer by default ('Warm start'), is compared cold; warm, the same plan
// again moves nothing, and the next plan reaches an equilibrium close to the
// cold one (the springs' equilibrium under a motion is not unique where
// tetrahedra turn over: the path matters).

#include <softface/models/interface.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(second_solve)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 3000);
  const Vector<double> lift =
    softface_tests::move_bone(scene, Point<3>(0, 0, 6));
  const Vector<double> turn =
    softface_tests::move_bone(scene, Point<3>(2, -1, 3), 12.);
  ParameterHandler prm;
  Models::declare_parameters(prm);
  const auto set_warm_start = [&prm](const bool warm) {
    prm.enter_subsection("Models");
    prm.enter_subsection("mass spring");
    prm.set("Warm start", warm);
    prm.leave_subsection();
    prm.leave_subsection();
  };
  set_warm_start(false);

  for (const std::string &name : Models::registered_names())
    {
      const auto reused = Models::create(name, prm);
      const auto fresh  = Models::create(name, prm);
      reused->setup(scene);
      fresh->setup(scene);
      Vector<double> first, second, again, reference;
      reused->solve(lift, first);
      reused->solve(turn, second);
      reused->solve(lift, again);
      fresh->solve(turn, reference);
      softface_tests::check_below(
        name + ": second plan vs a fresh model's, "
               "relative",
        softface_tests::relative_difference(second, reference),
        1e-12);
      softface_tests::check_below(name +
                                    ": first plan again vs its first answer, "
                                    "relative",
                                  softface_tests::relative_difference(again,
                                                                      first),
                                  1e-12);
    }

  set_warm_start(true);
  const auto warm = Models::create("mass spring", prm);
  const auto cold = Models::create("mass spring", prm);
  warm->setup(scene);
  cold->setup(scene);
  Vector<double> first, again, second, reference;
  warm->solve(lift, first);
  warm->solve(lift, again);
  softface_tests::check_equal("mass spring, warm: the same plan again, sweeps",
                              warm->statistics().iterations,
                              0);
  softface_tests::check_below(
    "mass spring, warm: the same plan again vs its first answer, relative",
    softface_tests::relative_difference(again, first),
    1e-14);
  warm->solve(turn, second);
  const unsigned int warm_sweeps = warm->statistics().iterations;
  cold->solve(turn, reference);
  deallog << "mass spring, the turn: sweeps cold "
          << cold->statistics().iterations << ", warm from the lift "
          << warm_sweeps << std::endl;
  softface_tests::check_below("mass spring, the turn warm vs cold, relative",
                              softface_tests::relative_difference(second,
                                                                  reference),
                              0.05);
}

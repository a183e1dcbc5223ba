// Every registered model, with its default parameters, set up once and
// solved for three plannings in turn (a lift, a turn with a shift, the lift
// again): the second plan's answer equals a fresh model's, and the repeated
// plan gives its first answer again, so nothing of one planning leaks into
// the next.

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
        1e-8);
      softface_tests::check_below(name +
                                    ": first plan again vs its first answer, "
                                    "relative",
                                  softface_tests::relative_difference(again,
                                                                      first),
                                  1e-8);
    }
}

// The nonlinear FEM model's linear solvers give the same answer: 'cg amg',
// 'gmres amg' and 'cg amg' with ML rebuilt on the tangent after every solve
// of more than one iteration ('AMG rebuild iterations = 1') agree with the
// direct solver to 1e-8 relative on the 6 mm lift with a turn (Neo-Hooke),
// and the rebuilds happen.

#include <softface/models/nonlinear_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(nonlinear_solvers)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 8000);
  const Vector<double> prescribed =
    softface_tests::move_bone(scene, Point<3>(0, 0, 6), 10.);

  Models::NonlinearFEM direct;
  direct.set_options("neo-hooke", "direct");
  direct.setup(scene);
  Vector<double> reference;
  direct.solve(prescribed, reference);
  softface_tests::print("direct: Newton iterations",
                        direct.report().newton_iterations);

  for (const auto &[solver, rebuild] :
       {std::make_pair(std::string("cg amg"), 100u),
        std::make_pair(std::string("gmres amg"), 100u),
        std::make_pair(std::string("cg amg"), 1u)})
    {
      Models::NonlinearFEM model;
      model.set_options("neo-hooke", solver);
      model.set_amg_rebuild_iterations(rebuild);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);
      const std::string name =
        solver + ", AMG rebuild iterations " + std::to_string(rebuild);
      softface_tests::check_below(
        name + ": relative difference to direct",
        softface_tests::relative_difference(u, reference),
        1e-8);
      softface_tests::print(name + ": Newton iterations",
                            model.report().newton_iterations);
      softface_tests::print(name + ": linear iterations",
                            model.report().linear_iterations);
      if (rebuild == 1)
        softface_tests::check_above(name + ": ML rebuilds",
                                    model.report().amg_rebuilds,
                                    1);
    }
}

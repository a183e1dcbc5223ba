// The three linear solvers give the same displacement on the cube of Mollemans
// et al. 2007 to 1e-8 relative; the direct solver factorises once and reuses
// the factorisation for later plannings; and the model is linear in the
// planning (twice the motion, twice the displacement).

#include <softface/models/linear_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(solvers_agree)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 8000);
  const Vector<double> lift =
    softface_tests::move_bone(scene, Point<3>(0, 0, 6));
  deallog << "tets: " << scene.triangulation.n_active_cells()
          << ", free DoFs: " << scene.n_free_dofs() << std::endl;

  Models::LinearFEM direct;
  direct.set_solver("direct", 0.);
  direct.setup(scene);
  Vector<double> reference;
  direct.solve(lift, reference);

  for (const std::string solver : {"gmres jacobi", "cg amg"})
    {
      Models::LinearFEM model;
      model.set_solver(solver, 1e-12);
      model.setup(scene);
      Vector<double> u;
      model.solve(lift, u);
      softface_tests::check_below(
        solver + ": relative difference to direct",
        softface_tests::relative_difference(u, reference),
        1e-8);
      softface_tests::print(solver + ": iterations",
                            model.statistics().iterations);
    }

  // Two more plannings: rotation by 10 degrees plus a sideways shift, and
  // twice that.
  const Vector<double> replan =
    softface_tests::move_bone(scene, Point<3>(3, 0, 1), 10.);
  Vector<double> u1, u2;
  direct.solve(replan, u1);
  Vector<double> doubled = replan;
  doubled *= 2.;
  direct.solve(doubled, u2);
  u1 *= 2.;
  softface_tests::check_equal("factorisations for three plannings",
                              direct.n_factorizations(),
                              1);
  softface_tests::check_below(
    "twice the planning: relative difference to twice the displacement",
    softface_tests::relative_difference(u2, u1),
    1e-12);

  Models::LinearFEM amg;
  amg.set_solver("cg amg", 1e-12);
  amg.setup(scene);
  Vector<double> u3;
  amg.solve(replan, u3);
  u1 /= 2.;
  softface_tests::check_below(
    "re-planned: relative difference between cg amg and direct",
    softface_tests::relative_difference(u3, u1),
    1e-8);
}

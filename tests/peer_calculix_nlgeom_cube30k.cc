// Nonlinear FEM (St. Venant-Kirchhoff) against CalculiX 2.20 NLGEOM on the
// same gmsh mesh and conditions (tests/data/cube30k/README.md): every nodal
// displacement agrees to 1e-4 relative to the largest, with the direct and
// the AMG-preconditioned solvers. CalculiX's linear answer differs by far
// more, so the comparison tells large-deformation from linear.

#include <softface/models/nonlinear_fem.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(peer_calculix_nlgeom_cube30k)
{
  ParameterHandler     prm;
  Scene                scene;
  const Vector<double> prescribed = softface_tests::read_peer_scene(prm, scene);
  const Vector<double> nlgeom =
    softface_tests::calculix_displacements(scene, "nl");
  const Vector<double> linear =
    softface_tests::calculix_displacements(scene, "lin");

  for (const std::string solver : {"direct", "cg amg"})
    {
      Models::NonlinearFEM model;
      model.set_options("st venant-kirchhoff", solver);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);
      softface_tests::check_below(solver +
                                    ": relative difference to CalculiX NLGEOM",
                                  softface_tests::relative_difference(u,
                                                                      nlgeom),
                                  1e-4);
      softface_tests::check_above(solver +
                                    ": relative difference to CalculiX linear",
                                  softface_tests::relative_difference(u,
                                                                      linear),
                                  1e-2);
      softface_tests::print(solver + ": Newton iterations",
                            model.report().newton_iterations);
    }
}

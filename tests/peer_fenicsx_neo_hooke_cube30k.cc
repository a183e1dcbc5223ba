// Nonlinear FEM with compressible Neo-Hooke against FEniCSx 0.5.2 on the same
// gmsh mesh and conditions (tests/data/cube30k/README.md): FEniCSx derives the
// residual and tangent from the stored energy
//   W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2
// by automatic differentiation, so it shares no code and no hand derivation
// with softface's law. Every nodal displacement agrees to 1e-8 relative to
// the largest (FEniCSx's Newton stopped at 1e-10 of the force, its file holds
// 12 digits), with the direct and the AMG-preconditioned solvers; CalculiX's
// St. Venant-Kirchhoff answer differs by far more, so the comparison tells
// the two laws apart.

#include <softface/models/nonlinear_fem.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(peer_fenicsx_neo_hooke_cube30k)
{
  ParameterHandler     prm;
  Scene                scene;
  const Vector<double> prescribed = softface_tests::read_peer_scene(prm, scene);
  const Vector<double> neo_hooke  = softface_tests::read_peer(
    scene,
    softface_tests::source_file(
      "data/cube30k/fenicsx_neo_hooke_displacements.csv"));
  const Vector<double> st_venant_kirchhoff =
    softface_tests::calculix_displacements(scene, "nl");

  for (const std::string solver : {"direct", "cg amg"})
    {
      Models::NonlinearFEM model;
      model.set_options("neo-hooke", solver);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);
      softface_tests::check_below(
        solver + ": relative difference to FEniCSx Neo-Hooke",
        softface_tests::relative_difference(u, neo_hooke),
        1e-8);
      softface_tests::check_above(
        solver + ": relative difference to CalculiX St. Venant-Kirchhoff",
        softface_tests::relative_difference(u, st_venant_kirchhoff),
        1e-2);
      softface_tests::print(solver + ": Newton iterations",
                            model.report().newton_iterations);
    }
}

// Nonlinear FEM (St. Venant-Kirchhoff) against CalculiX 2.20 NLGEOM on the
// same gmsh mesh and conditions (tests/data/cube30k/README.md): every nodal
// displacement agrees to 1e-4 relative to the largest, with the direct and
// the AMG-preconditioned solvers. CalculiX's linear answer differs by far
// more, so the comparison tells large-deformation from linear.

#include <softface/models/nonlinear_fem.h>
#include <softface/core/planning.h>
#include <softface/simulator/simulator.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(peer_calculix_nlgeom_cube30k)
{
  ParameterHandler prm;
  Simulator::read_parameters(
    softface_tests::source_file("peer_calculix_cube30k.prm"), prm);
  Scene scene;
  scene.parse_parameters(prm, softface_tests::source_file(""));
  Planning planning;
  planning.parse_parameters(prm, scene);
  const Vector<double> prescribed = planning.prescribed_displacement(scene);
  const Vector<double> nlgeom =
    softface_tests::read_peer(scene,
                              softface_tests::source_file(
                                "data/cube30k/calculix_nl_displacements.csv"));
  const Vector<double> linear =
    softface_tests::read_peer(scene,
                              softface_tests::source_file(
                                "data/cube30k/calculix_lin_displacements.csv"));

  for (const std::string solver : {"direct", "cg amg"})
    {
      Models::NonlinearFEM model;
      model.set_options("st venant-kirchhoff", solver);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);
      softface_tests::check(softface_tests::relative_difference(u, nlgeom) <
                              1e-4,
                            solver +
                              ": equals CalculiX NLGEOM to 1e-4 relative");
      softface_tests::check(softface_tests::relative_difference(u, linear) >
                              1e-2,
                            solver +
                              ": differs from CalculiX linear by over 1e-2");
    }
}

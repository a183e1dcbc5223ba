// softface's linear FEM against CalculiX 2.20 (C3D4, linear static, direct
// solver) on the same gmsh mesh and conditions (tests/data/cube30k/README.md):
// every nodal displacement agrees to 1e-6 relative to the largest. The scene
// comes from peer_calculix_cube30k.prm through the whole parameter path.
// Both the direct and the AMG solver must meet it; CalculiX's nonlinear
// (NLGEOM) answer must not (so the comparison can tell them apart).

#include <deal.II/base/utilities.h>

#include <softface/models/interface.h>
#include <softface/models/linear_fem.h>
#include <softface/core/planning.h>
#include <softface/core/scene.h>
#include <softface/simulator/simulator.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

#include <fstream>
#include <map>

using namespace softface;


SOFTFACE_TEST(peer_calculix_cube30k)
{
  ParameterHandler prm;
  Simulator::read_parameters(
    softface_tests::source_file("peer_calculix_cube30k.prm"), prm);
  Scene scene;
  scene.parse_parameters(prm, softface_tests::source_file(""));
  Planning planning;
  planning.parse_parameters(prm, scene);
  deallog << "tets: " << scene.triangulation.n_active_cells()
          << ", vertices: " << scene.n_vertices()
          << ", join points: " << scene.n_join_vertices(0) << " fixed + "
          << scene.n_join_vertices(1) << " bone" << std::endl;

  const Vector<double> linear =
    softface_tests::read_peer(scene,
                              softface_tests::source_file(
                                "data/cube30k/calculix_lin_displacements.csv"));
  const Vector<double> nonlinear =
    softface_tests::read_peer(scene,
                              softface_tests::source_file(
                                "data/cube30k/calculix_nl_displacements.csv"));
  const Vector<double> prescribed = planning.prescribed_displacement(scene);

  auto model = Models::create("linear fem", prm);
  model->setup(scene);
  Vector<double> u;
  model->solve(prescribed, u);
  softface_tests::check(softface_tests::relative_difference(u, linear) < 1e-6,
                        "direct: equals CalculiX linear to 1e-6 relative");
  softface_tests::check(softface_tests::relative_difference(u, nonlinear) >
                          1e-2,
                        "direct: differs from CalculiX NLGEOM by over 1e-2");

  Models::LinearFEM amg;
  amg.set_solver("cg amg", 1e-12);
  amg.setup(scene);
  amg.solve(prescribed, u);
  softface_tests::check(softface_tests::relative_difference(u, linear) < 1e-6,
                        "cg amg: equals CalculiX linear to 1e-6 relative");
}

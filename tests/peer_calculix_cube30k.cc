// softface's linear FEM against CalculiX 2.20 (C3D4, linear static, direct
// solver) on the same gmsh mesh and conditions (tests/data/cube30k/README.md):
// every nodal displacement agrees to 1e-6 relative to the largest. The scene
// comes from peer_calculix_cube30k.prm through the whole parameter path.
// Both the direct and the AMG solver must meet it; CalculiX's nonlinear
// (NLGEOM) answer must not (so the comparison can tell them apart).

#include <softface/models/linear_fem.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(peer_calculix_cube30k)
{
  ParameterHandler     prm;
  Scene                scene;
  const Vector<double> prescribed = softface_tests::read_peer_scene(prm, scene);
  deallog << "tets: " << scene.triangulation.n_active_cells()
          << ", vertices: " << scene.n_vertices()
          << ", join points: " << scene.n_join_vertices(0) << " fixed + "
          << scene.n_join_vertices(1) << " bone" << std::endl;
  const Vector<double> linear =
    softface_tests::calculix_displacements(scene, "lin");
  const Vector<double> nonlinear =
    softface_tests::calculix_displacements(scene, "nl");

  auto model = Models::create("linear fem", prm);
  model->setup(scene);
  Vector<double> u;
  model->solve(prescribed, u);
  softface_tests::check_below("direct: relative difference to CalculiX linear",
                              softface_tests::relative_difference(u, linear),
                              1e-6);
  softface_tests::check_above("direct: relative difference to CalculiX NLGEOM",
                              softface_tests::relative_difference(u, nonlinear),
                              1e-2);

  Models::LinearFEM amg;
  amg.set_solver("cg amg", 1e-12);
  amg.setup(scene);
  amg.solve(prescribed, u);
  softface_tests::check_below("cg amg: relative difference to CalculiX linear",
                              softface_tests::relative_difference(u, linear),
                              1e-6);
}

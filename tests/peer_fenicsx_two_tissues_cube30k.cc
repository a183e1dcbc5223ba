// Heterogeneous tissue against FEniCSx 0.5.2 (tests/data/cube30k_two_tissues/
// README.md): the peer cube with its tissue in two parts, E = 3000 Pa and
// Poisson's ratio 0.46 for x < 40 mm, E = 9000 Pa and 0.3 beyond, each cell's
// Lame coefficients a piecewise-constant field in FEniCSx. Linear FEM agrees
// with it to 1e-8 of the largest displacement (direct and AMG solvers). With
// the second tissue's Poisson's ratio left at Material's 0.46 (what softface
// would compute if it ignored the per-tissue ratio), the answer is far from
// the peer, so the comparison sees the ratio and not only the modulus.

#include <softface/effects/interface.h>
#include <softface/models/linear_fem.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  // Linear FEM's answer on the scene of @p prm, its tissues made by
  // Effects/heterogeneous tissue as the simulator does, with the given solver.
  Vector<double>
  solve(ParameterHandler &prm, const std::string &solver)
  {
    Scene scene;
    scene.parse_parameters(prm, softface_tests::source_file(""));
    Effects::create("heterogeneous tissue", prm)->apply(scene);
    Planning planning;
    planning.parse_parameters(prm, scene);
    Models::LinearFEM model;
    model.set_solver(solver, 1e-12);
    model.setup(scene);
    Vector<double> u;
    model.solve(planning.prescribed_displacement(scene), u);
    return u;
  }
} // namespace

SOFTFACE_TEST(peer_fenicsx_two_tissues_cube30k)
{
  ParameterHandler prm;
  Scene            scene;
  softface_tests::read_scene("peer_fenicsx_two_tissues_cube30k.prm",
                             prm,
                             scene);
  unsigned int n_second = 0;
  for (const auto &cell : scene.triangulation.active_cell_iterators())
    n_second += (cell->material_id() == 3);
  deallog << "tetrahedra of the second tissue: " << n_second << std::endl;
  const Vector<double> peer = softface_tests::read_peer(
    scene,
    softface_tests::source_file(
      "data/cube30k_two_tissues/fenicsx_linear_displacements.csv"));

  for (const std::string solver : {"direct", "cg amg"})
    softface_tests::check_below(
      solver + ": relative difference to FEniCSx",
      softface_tests::relative_difference(solve(prm, solver), peer),
      1e-8);

  prm.enter_subsection("Effects");
  prm.enter_subsection("heterogeneous tissue");
  prm.set("Poisson's ratios", "");
  prm.leave_subsection();
  prm.leave_subsection();
  softface_tests::check_above(
    "every tissue at Poisson's ratio 0.46: relative difference to FEniCSx",
    softface_tests::relative_difference(solve(prm, "direct"), peer),
    1e-2);
}

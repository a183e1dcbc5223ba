// The default scene, prm/default.prm (what ./run.sh runs), through the
// whole simulator: all four models on the 35k-tetrahedron cube of Mollemans et
// al. 2007. The printed table pins down every model's figures (iterations,
// largest displacement, difference to linear FEM, precision, inverted
// tetrahedra).

#include "run_scene.h"

SOFTFACE_TEST(run_default_scene)
{
  softface::Simulator simulator;
  const int           exit_code = softface_tests::run_scene(
    simulator, softface_tests::source_file("../prm/default.prm"));
  softface_tests::check_equal("exit code", exit_code, 0);
  softface_tests::check_equal("models run", simulator.runs().size(), 4);
}

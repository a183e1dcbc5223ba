// Every registered kind of model side by side on one scene through the whole
// simulator: the table (counts, iterations, largest displacement, difference
// to linear FEM), each model's figures, the mass spring model's warning. The
// join points move as planned in every model (largest |u| = the bone's
// largest motion), and the models that solve elasticity agree with linear
// FEM to within their model error (checked by the printed differences).

#include "run_scene.h"

SOFTFACE_TEST(run_multi_model)
{
  softface::Simulator simulator;
  const int           exit_code = softface_tests::run_scene(
    simulator, softface_tests::source_file("run_multi_model.prm"));
  softface_tests::check_equal("exit code", exit_code, 0);
  softface_tests::check_equal("models run", simulator.runs().size(), 5);
}

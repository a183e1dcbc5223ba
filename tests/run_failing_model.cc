// Failing models are isolated: the mass tensor and mass spring models stop
// after 'Maximum sweeps' with their reasons (the largest gradient, the
// largest pending step), linear FEM still runs and reports, the run ends
// with exit code 1, and summary.csv has a 'failed' row for each.

#include <deal.II/base/utilities.h>

#include "run_scene.h"

#include <fstream>

SOFTFACE_TEST(run_failing_model)
{
  softface::Simulator simulator;
  const int           exit_code = softface_tests::run_scene(
    simulator, softface_tests::source_file("run_failing_model.prm"));
  softface_tests::check_equal("exit code", exit_code, 1);

  std::ifstream in("run_failing_model_output/summary.csv");
  std::string   line;
  std::getline(in, line);
  unsigned int n_failed = 0, n_ok = 0;
  while (std::getline(in, line))
    {
      n_failed += line.find(",failed,") != std::string::npos;
      n_ok += line.find(",ok,") != std::string::npos;
    }
  softface_tests::check_equal("summary.csv rows with status failed",
                              n_failed,
                              2);
  softface_tests::check_equal("summary.csv rows with status ok", n_ok, 1);
}

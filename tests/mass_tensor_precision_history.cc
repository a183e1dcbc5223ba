// The per-sweep precision history of the MTM (Mollemans et al. 2007,
// Sec. 2.3.5, Fig. 1), which benchmarks/run_all.sh plots. Without the active
// set every sweep updates every free point in the same order, so the iterates
// do not depend on the stop threshold: the history of a long run at sweep N
// must equal the precision that "Report precision" measures independently for a
// run that stopped after N sweeps (to the six digits the CSV holds), and the
// history must end converged.

#include <softface/models/mass_tensor.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(mass_tensor_precision_history)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 8000);
  const Vector<double> lift =
    softface_tests::move_bone(scene, Point<3>(0, 0, 6));

  Models::MassTensor long_run, short_run;
  long_run.set_scheme(true, 1e-6, 10, false);
  long_run.set_precision_history_file("mass_tensor_precision_history.csv");
  short_run.set_scheme(true, 1e-3, 10, false);
  short_run.set_report_precision(true);
  Vector<double> u_long, u_short;
  long_run.setup(scene);
  long_run.solve(lift, u_long);
  short_run.setup(scene);
  short_run.solve(lift, u_short);

  // sweep,precision_max,precision_mean,max_gradient,active_points
  std::ifstream                    in("mass_tensor_precision_history.csv");
  std::string                      line;
  std::vector<std::vector<double>> rows;
  std::getline(in, line);
  while (std::getline(in, line))
    {
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream  fields(line);
      std::vector<double> row(5);
      for (double &x : row)
        fields >> x;
      rows.push_back(row);
    }
  const unsigned int N = short_run.report().sweeps;
  softface_tests::check_equal("history rows (one per sweep)",
                              rows.size(),
                              long_run.report().sweeps);
  softface_tests::print("sweeps of the long run", long_run.report().sweeps);
  softface_tests::print("sweeps of the short run", N);
  softface_tests::check_equal("the short run stopped within the long run's "
                              "history (sweep N has a row)",
                              N < rows.size() && rows[N - 1][0] == N,
                              1);
  const auto &at_N = rows[N - 1];
  // The CSV holds six significant digits.
  const auto relative = [](const double a, const double b) {
    return std::abs(a - b) / std::max(std::abs(b), 1e-300);
  };
  softface_tests::print("precision max at sweep N (mm)",
                        short_run.report().precision_max,
                        4);
  softface_tests::check_below(
    "history at sweep N vs the short run's reported precision max, relative",
    relative(at_N[1], short_run.report().precision_max),
    1e-5);
  softface_tests::check_below(
    "history at sweep N vs the short run's reported precision mean, relative",
    relative(at_N[2], short_run.report().precision_mean),
    1e-5);
  softface_tests::check_below(
    "history at sweep N vs the short run's max gradient, relative",
    relative(at_N[3], short_run.report().max_gradient),
    1e-5);
  softface_tests::check_above("precision max after the first sweep (mm)",
                              rows.front()[1],
                              1.);
  softface_tests::check_below("precision max after the last sweep (mm)",
                              rows.back()[1],
                              1e-3,
                              1);
}

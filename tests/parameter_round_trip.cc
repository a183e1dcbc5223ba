// Parameter files fed back in. (1) 'softface --print-parameters' reads back
// and prints the same text. (2) A scene whose mesh and evaluation points are
// relative to its folder runs; the expanded parameters.prm it writes runs
// again from another folder with the same answers, and writes the same
// parameters.prm (its files absolute, everything else as it was).

#include <softface/simulator/simulator.h>

#include "tests.h"

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace softface;

namespace
{
  std::string
  contents(const std::string &filename)
  {
    std::ifstream      in(filename);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // The first line where two texts differ (0: none).
  unsigned int
  first_difference(const std::string &a, const std::string &b)
  {
    std::istringstream x(a), y(b);
    std::string        line_x, line_y;
    for (unsigned int line = 1;; ++line)
      {
        const bool more_x = static_cast<bool>(std::getline(x, line_x));
        const bool more_y = static_cast<bool>(std::getline(y, line_y));
        if (!more_x && !more_y)
          return 0;
        if (more_x != more_y || line_x != line_y)
          return line;
      }
  }
} // namespace

SOFTFACE_TEST(parameter_round_trip)
{
  namespace fs = std::filesystem;
  fs::create_directories("parameter_round_trip_elsewhere");

  std::ostringstream defaults;
  Simulator::print_default_parameters(defaults);
  std::ofstream("parameter_round_trip_elsewhere/defaults.prm")
    << defaults.str();
  ParameterHandler prm;
  Simulator::read_parameters("parameter_round_trip_elsewhere/defaults.prm",
                             prm);
  std::ostringstream read_back;
  prm.print_parameters(read_back, ParameterHandler::PRM);
  softface_tests::check_equal("defaults: first line printed differently",
                              first_difference(defaults.str(), read_back.str()),
                              0);

  Simulator          first;
  std::ostringstream out, err;
  softface_tests::check_equal("scene: exit code",
                              first.run(softface_tests::source_file(
                                          "parameter_round_trip.prm"),
                                        out,
                                        err),
                              0);
  const std::string expanded =
    contents("parameter_round_trip_output/parameters.prm");
  fs::copy_file("parameter_round_trip_output/parameters.prm",
                "parameter_round_trip_elsewhere/parameters.prm",
                fs::copy_options::overwrite_existing);

  Simulator again;
  softface_tests::check_equal(
    "its parameters.prm, from another folder: exit code",
    again.run("parameter_round_trip_elsewhere/parameters.prm", out, err),
    0);
  softface_tests::check_equal(
    "its parameters.prm: first line written differently",
    first_difference(expanded,
                     contents("parameter_round_trip_output/parameters.prm")),
    0);
  softface_tests::check_equal("models run",
                              again.runs().size(),
                              first.runs().size());
  for (unsigned int r = 0; r < first.runs().size(); ++r)
    {
      Vector<double> difference = again.runs()[r].displacement;
      difference -= first.runs()[r].displacement;
      softface_tests::print(first.runs()[r].model + ": |u| (l2, mm)",
                            first.runs()[r].displacement.l2_norm(),
                            6);
      softface_tests::check_below(first.runs()[r].model + ": max |u again - u|",
                                  difference.linfty_norm(),
                                  0.);
    }
  softface_tests::check_equal(
    "evaluation points written again",
    fs::exists("parameter_round_trip_output/evaluation_linear_fem.csv"),
    1);
}

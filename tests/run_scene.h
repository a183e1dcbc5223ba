#ifndef softface_tests_run_scene_h
#define softface_tests_run_scene_h

// Scene tests: run a tests/<name>.prm through the whole simulator and print
// what it reports without timings (the side-by-side table, the comparison,
// each model's figures, warnings and errors) and its exit code, so that
// numdiff compares every figure with tests/<name>.output.

#include <softface/outputs/report.h>
#include <softface/simulator/simulator.h>

#include "tests.h"

#include <sstream>
#include <string>

namespace softface_tests
{
  using namespace softface;

  /// Each line of @p text to deallog.
  inline void
  log_lines(const std::string &text)
  {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
      if (!line.empty())
        deallog << line << std::endl;
  }

  /// Run @p prm_file (a path) and print the report and what went to
  /// stderr; returns the exit code.
  inline int
  run_scene(Simulator &simulator, const std::string &prm_file)
  {
    std::ostringstream out, err;
    const int          exit_code = simulator.run(prm_file, out, err);
    std::ostringstream report;
    Report::print(simulator.scene(),
                  simulator.runs(),
                  simulator.reference_model(),
                  false,
                  report);
    log_lines(report.str());
    log_lines(err.str());
    return exit_code;
  }

  /**
   * Run the phantom patient scene tests/@p prm_name through the simulator
   * and check what every patient run needs: exit code 0, between 4000 and
   * 16000 tetrahedra, at least @p min_join_points join points per segment.
   */
  inline void
  run_patient_scene(Simulator         &simulator,
                    const std::string &prm_name,
                    const double       min_join_points)
  {
    std::ostringstream out, err;
    const int exit_code = simulator.run(source_file(prm_name), out, err);
    check_equal("exit code", exit_code, 0);
    const Scene &scene = simulator.scene();
    check_within(
      "tetrahedra", scene.triangulation.n_active_cells(), 4000, 16000, 9);
    for (unsigned int s = 0; s < scene.segments.size(); ++s)
      check_within(scene.segments[s].name + ": join points",
                   scene.n_join_vertices(s),
                   min_join_points,
                   1e9,
                   9);
  }

  /// A patient run's motion: the largest |u - planned| over the join points
  /// and the largest |u| over the free points (mm).
  struct JoinAndFreeMotion
  {
    double join_error   = 0.;
    double free_largest = 0.;
  };

  inline JoinAndFreeMotion
  join_and_free_motion(const Scene          &scene,
                       const Vector<double> &u,
                       const Vector<double> &planned)
  {
    JoinAndFreeMotion motion;
    for (const auto &dofs : scene.vertex_dofs())
      {
        Tensor<1, 3> v, e;
        for (unsigned int c = 0; c < 3; ++c)
          {
            v[c] = u[dofs[c]];
            e[c] = v[c] - planned[dofs[c]];
          }
        if (scene.join_dofs()[dofs[0]])
          motion.join_error = std::max(motion.join_error, e.norm());
        else
          motion.free_largest = std::max(motion.free_largest, v.norm());
      }
    return motion;
  }
} // namespace softface_tests

#endif

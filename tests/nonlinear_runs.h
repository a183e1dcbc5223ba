#ifndef softface_tests_nonlinear_runs_h
#define softface_tests_nonlinear_runs_h

// One nonlinear FEM solve of a planning with the load-stepping options set
// as a scene would set them, and how far it got (the nonlinear_* tests).

#include <softface/core/error.h>
#include <softface/core/planning.h>
#include <softface/core/tetrahedron.h>
#include <softface/models/nonlinear_fem.h>

#include <algorithm>
#include <string>

namespace softface_tests
{
  using namespace softface;

  struct NonlinearOutcome
  {
    bool           converged = false;
    double         load      = 0.;
    unsigned int   cutbacks  = 0;
    unsigned int   newton    = 0;
    std::string    message;
    Vector<double> u;
  };

  /// Options of a nonlinear solve as a scene's parameters spell them.
  struct NonlinearOptions
  {
    std::string law;
    /// "rigid": the planning's rigid load path, as the simulator gives it;
    /// "linear": the final displacement scaled.
    std::string path               = "rigid";
    std::string predictor          = "tangent";
    std::string corrector          = "newton";
    std::string indefinite_tangent = "lu";
    std::string minimum_increment  = "0.001";
    /// Solve the planning this fraction of the way along the path.
    double load = 1.;
  };

  inline NonlinearOutcome
  solve_nonlinear(const Scene            &scene,
                  const Planning         &planning,
                  const NonlinearOptions &options)
  {
    ParameterHandler prm;
    Models::NonlinearFEM::declare_parameters(prm);
    prm.set("Material law", options.law);
    prm.set("Solver", "direct");
    prm.set("Load path", options.path);
    prm.set("Predictor", options.predictor);
    prm.set("Nonlinear solver", options.corrector);
    prm.set("Indefinite tangent", options.indefinite_tangent);
    prm.set("Minimum load increment", options.minimum_increment);
    Models::NonlinearFEM model;
    model.parse_parameters(prm);
    const double              end = options.load;
    const Models::PlanContext plan{[&](const double load) {
      return planning.prescribed_displacement(scene, load * end);
    }};
    model.setup(scene);
    NonlinearOutcome outcome;
    try
      {
        Vector<double> target = planning.prescribed_displacement(scene, end);
        if (options.path == "linear")
          {
            target = planning.prescribed_displacement(scene);
            target *= end;
          }
        model.solve(target, outcome.u, plan);
        outcome.converged = true;
      }
    catch (const Error &e)
      {
        outcome.message = e.what();
      }
    const auto &report = model.report();
    outcome.load       = end * (outcome.converged ? 1. : report.load_reached);
    outcome.cutbacks   = report.cutbacks;
    outcome.newton     = report.newton_iterations;
    return outcome;
  }

  inline NonlinearOutcome
  solve_nonlinear(const Scene       &scene,
                  const Planning    &planning,
                  const std::string &law,
                  const std::string &path,
                  const std::string &predictor,
                  const std::string &corrector         = "newton",
                  const std::string &minimum_increment = "0.001")
  {
    NonlinearOptions options;
    options.law               = law;
    options.path              = path;
    options.predictor         = predictor;
    options.corrector         = corrector;
    options.minimum_increment = minimum_increment;
    return solve_nonlinear(scene, planning, options);
  }

  /// The smallest volume ratio det F over the (P1) cells displaced by @p u.
  inline double
  min_volume_ratio(const Scene &scene, const Vector<double> &u)
  {
    double smallest = std::numeric_limits<double>::max();
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      {
        const Tetrahedron::Vertices x = Tetrahedron::vertices(cell);
        Tetrahedron::Vertices       y = x;
        for (unsigned int k = 0; k < 4; ++k)
          for (unsigned int c = 0; c < 3; ++c)
            y[k][c] += u[scene.vertex_dofs()[cell->vertex_index(k)][c]];
        smallest = std::min(smallest,
                            Tetrahedron::signed_volume(y) /
                              Tetrahedron::signed_volume(x));
      }
    return smallest;
  }
} // namespace softface_tests

#endif

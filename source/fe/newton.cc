// Newton's method with load stepping, line search and cut-back (fe), for the
// nonlinear FEM models on any layout: they provide forces and tangent, this
// drives the join DoFs to the planned motion.

#include <softface/core/error.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/newton.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace softface
{
  void
  LoadSteppedNewton::Parameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Initial load increment",
                      "1",
                      Patterns::Double(0., 1.),
                      "Fraction of the planned motion tried in the first "
                      "load step; later steps grow after quick convergence "
                      "and are halved after a failure.");
    prm.declare_entry("Minimum load increment",
                      "0.001",
                      Patterns::Double(0., 1.),
                      "A step that still fails at this increment ends the "
                      "solve with an error giving the load reached, the "
                      "residual and the reason. Must be positive.");
    prm.declare_entry("Maximum Newton iterations",
                      "20",
                      Patterns::Integer(1),
                      "Newton iterations per load step before it counts as "
                      "failed.");
    prm.declare_entry("Residual tolerance",
                      "1e-10",
                      Patterns::Double(0., 1.),
                      "Newton stops when the free DoFs' residual force is "
                      "below this fraction of the largest unbalanced force "
                      "a load step started with.");
  }

  void
  LoadSteppedNewton::Parameters::parse_parameters(ParameterHandler  &prm,
                                                  const std::string &model)
  {
    initial_increment  = prm.get_double("Initial load increment");
    minimum_increment  = prm.get_double("Minimum load increment");
    max_iterations     = prm.get_integer("Maximum Newton iterations");
    residual_tolerance = prm.get_double("Residual tolerance");
    if (!(initial_increment > 0.))
      throw Error(model + ": 'Initial load increment' must be positive.");
    // Halving a failing step must end somewhere.
    if (!(minimum_increment > 0.))
      throw Error(model + ": 'Minimum load increment' must be positive.");
  }

  LoadSteppedNewton::LoadSteppedNewton(
    const Parameters                   &parameters,
    const Evaluate                     &evaluate,
    SparseMatrix<double>               &tangent,
    const std::vector<bool>            &is_join,
    LinearSolver                       &linear_solver,
    const std::function<std::string()> &where_refused)
      : prm(parameters)
      , evaluate(evaluate)
      , tangent(tangent)
      , is_join(is_join)
      , linear_solver(linear_solver)
      , where_refused(where_refused)
  {}

  bool
  LoadSteppedNewton::unbalanced_forces(
    const Vector<double> &u,
    const double          load,
    Vector<double>       &forces,
    SparseMatrix<double> *tangent_matrix) const
  {
    if (!evaluate(u, forces, tangent_matrix))
      return false;
    if (external != nullptr)
      forces.add(-load, *external);
    return true;
  }

  LoadSteppedNewton::StepResult
  LoadSteppedNewton::step(Vector<double>       &u,
                          const Vector<double> &target,
                          const double          load,
                          TimerOutput          &timer,
                          std::ostream         *progress)
  {
    const unsigned int n = u.size();
    StepResult         result;
    // What the holding constraints take up is not unbalanced.
    Vector<double> condensed;
    const auto     free_norm = [&](const Vector<double> &v) {
      if (constraints == nullptr)
        return ConstrainedSystem::free_norm(is_join, v);
      condensed = v;
      constraints->condense(condensed);
      return ConstrainedSystem::free_norm(is_join, condensed);
    };
    Vector<double> closing;

    // The first iteration carries the join DoFs to the step's target.
    Vector<double> join_increment(n);
    for (unsigned int i = 0; i < n; ++i)
      if (is_join[i])
        join_increment[i] = target[i] - u[i];

    Vector<double> forces(n), rhs(n), du(n), trial(n), trial_forces(n);
    // The accepted line-search point was evaluated with its tangent, so the
    // next iteration starts from it without assembling again.
    bool evaluated = false;
    for (unsigned int it = 0; it <= prm.max_iterations; ++it)
      {
        Timer              iteration_timer;
        const unsigned int linear_before = report.linear_iterations;
        const bool         first         = (it == 0);
        {
          TimerOutput::Scope scope(timer, "assembly");
          if (!evaluated && !unbalanced_forces(u, load, forces, &tangent))
            {
              result.reason = "a tetrahedron is inverted" +
                              (where_refused ? where_refused() : "");
              return result;
            }
        }
        const double residual = free_norm(forces);
        result.residual       = residual / std::max(reference_force, 1e-300);
        if (!first && residual <= prm.residual_tolerance * reference_force)
          {
            result.converged = true;
            return result;
          }
        if (it == prm.max_iterations)
          break;

        {
          TimerOutput::Scope scope(timer, "assembly");
          ConstrainedSystem::right_hand_side(
            tangent, is_join, join_increment, &forces, rhs);
          ConstrainedSystem::eliminate_join_dofs(is_join, tangent);
          if (constraints != nullptr)
            {
              // du = closing + C x: C^T K C x = C^T (rhs - K closing).
              constraints->closing_increment(u, *bone, load, closing);
              Vector<double> K_closing(n);
              tangent.vmult(K_closing, closing);
              rhs -= K_closing;
              constraints->condense(tangent);
              constraints->condense(rhs);
            }
        }
        if (first)
          {
            reference_force = std::max(reference_force, free_norm(rhs));
            if (reference_force == 0.)
              {
                // Nothing is unbalanced (e.g. every vertex is a join point):
                // the join DoFs still move.
                u += join_increment;
                result.converged = true;
                return result;
              }
          }

        LinearSolver::Result solve;
        {
          TimerOutput::Scope scope(timer, "linear solves");
          const unsigned int builds_before = linear_solver.n_amg_builds();
          du                               = 0.;
          if (linear_solver.set_matrix(tangent))
            solve = linear_solver.solve(rhs, du);
          else
            {
              solve.not_positive_definite = true;
              solve.iterations            = 1;
            }
          report.linear_iterations += solve.iterations;
          report.amg_rebuilds += linear_solver.n_amg_builds() - builds_before;
        }
        if (solve.not_positive_definite)
          result.reason = "the tangent is not positive definite";
        else if (solve.negative_curvature)
          result.reason = "the tangent is not positive definite (CG found "
                          "negative curvature after " +
                          std::to_string(solve.iterations) + " iterations)";
        else if (!solve.converged)
          result.reason = linear_solver.parameters().method +
                          " did not converge (" +
                          std::to_string(solve.iterations) + " iterations)";
        if (!solve.converged)
          return result;
        ++result.iterations;
        if (constraints != nullptr)
          {
            constraints->lines().distribute(du);
            du += closing;
          }
        for (unsigned int i = 0; i < n; ++i)
          if (is_join[i])
            du[i] = join_increment[i];

        // Backtracking on the residual norm; the predictor (which moves the
        // join DoFs) is taken whole or the step fails.
        bool accepted = false;
        for (double alpha = 1.; alpha > 1. / 64 && !accepted; alpha /= 2)
          {
            trial = u;
            trial.add(alpha, du);
            bool valid;
            {
              TimerOutput::Scope scope(timer, "assembly");
              valid = unbalanced_forces(trial, load, trial_forces, &tangent);
            }
            if (valid && (first || free_norm(trial_forces) <=
                                     (1. - 1e-4 * alpha) * residual))
              accepted = true;
            if (first)
              break;
          }
        if (!accepted)
          {
            result.reason =
              first ? "the predictor inverts a tetrahedron" +
                        (where_refused ? where_refused() : std::string()) :
                      "the line search found no descent";
            return result;
          }
        u.swap(trial);
        forces.swap(trial_forces);
        evaluated      = true;
        join_increment = 0.;

        // Large (quadratic reference) solves take minutes: say where they
        // are once an iteration is slow enough for anyone to wonder.
        if (progress != nullptr && iteration_timer.wall_time() > 5.)
          {
            std::ostringstream line;
            line << "        Newton iteration " << result.iterations << ": ";
            if (first)
              line << "predictor (join points moved), ";
            else
              line << "relative residual before " << std::setprecision(2)
                   << result.residual << ", ";
            line << report.linear_iterations - linear_before
                 << " linear iterations, " << std::fixed << std::setprecision(1)
                 << iteration_timer.wall_time() << " s\n";
            *progress << line.str() << std::flush;
          }
      }
    result.reason =
      "no convergence in " + std::to_string(prm.max_iterations) + " iterations";
    return result;
  }

  void
  LoadSteppedNewton::set_vertex_constraints(
    VertexConstraintSet  *set,
    const Vector<double> *bone_motion,
    const unsigned int    max_active_set_rounds)
  {
    constraints = set;
    bone        = bone_motion;
    max_rounds  = max_active_set_rounds;
  }

  LoadSteppedNewton::Report
  LoadSteppedNewton::solve(const Vector<double> &join_motion,
                           Vector<double>       &u,
                           TimerOutput          &timer,
                           std::ostream         *progress,
                           const std::string    &description,
                           const std::string    &hint,
                           const Vector<double> *external_forces)
  {
    external             = external_forces;
    const unsigned int n = join_motion.size();
    report               = Report();
    reference_force      = 0.;
    u.reinit(n);
    Vector<double> converged = u, target(n);
    double         load = 0., increment = prm.initial_increment;
    while (load < 1.)
      {
        const double next = std::min(1., load + increment);
        target.equ(next, join_motion);
        StepResult result = step(u, target, next, timer, progress);
        // Unilateral constraints: release those that pull, hold those
        // passed through, and solve the step again until none changes.
        for (unsigned int round = 1;
             result.converged && constraints != nullptr &&
             constraints->has_unilateral();
             ++round)
          {
            Vector<double> forces(n);
            unbalanced_forces(u, next, forces, nullptr);
            if (constraints->update_active_set(u, *bone, forces, next) == 0)
              break;
            if (round == max_rounds)
              {
                result.converged = false;
                result.reason    = "the contact's active set still changed "
                                   "after " +
                                std::to_string(max_rounds) +
                                " solves ('Maximum active-set iterations')";
                break;
              }
            const unsigned int before = result.iterations;
            result                    = step(u, target, next, timer, progress);
            result.iterations += before;
          }
        if (result.converged)
          {
            load      = next;
            converged = u;
            ++report.load_steps;
            report.newton_iterations += result.iterations;
            report.iterations_per_step.push_back(result.iterations);
            report.final_residual = result.residual;
            if (progress != nullptr)
              {
                std::ostringstream line;
                line << "      load step " << report.load_steps << ": load "
                     << load << ", " << result.iterations
                     << " Newton iterations, relative residual "
                     << std::setprecision(2) << result.residual << '\n';
                *progress << line.str() << std::flush;
              }
            if (result.iterations <= 4)
              increment *= 2.;
            increment = std::min(increment, 1. - load);
            if (!std::isfinite(u.l2_norm()))
              throw Error(description + ": the displacement became NaN.");
          }
        else
          {
            u = converged;
            ++report.cutbacks;
            if (progress != nullptr)
              {
                std::ostringstream line;
                line << "      load " << next << " failed (" << result.reason
                     << "), cutting back\n";
                *progress << line.str() << std::flush;
              }
            report.newton_iterations += result.iterations;
            increment /= 2.;
            if (increment < prm.minimum_increment)
              {
                std::ostringstream m;
                m << description << ": load step " << report.load_steps + 1
                  << " failed at load " << next
                  << " of the planning: " << result.reason
                  << " (relative residual " << result.residual
                  << "); the increment fell below " << prm.minimum_increment
                  << " after " << report.cutbacks
                  << " cut-backs. Last converged load: " << load << "." << hint;
                throw Error(m.str());
              }
          }
      }
    return report;
  }
} // namespace softface

// Newton's method with load stepping, line search and cut-back (fe), for the
// nonlinear FEM models on any layout: they provide forces and tangent, this
// drives the join DoFs to the planned motion.

#include <deal.II/lac/sparse_direct.h>
#include <deal.II/sundials/kinsol.h>

#include <softface/core/error.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/newton.h>
#include <softface/fe/sparse_cholesky.h>

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
    prm.declare_entry("Predictor",
                      "tangent",
                      Patterns::Selection("tangent|secant|join only"),
                      "How a load step starts once the join points are at "
                      "its target: 'tangent' moves the free points by the "
                      "tangent system's answer (its free part halved, down "
                      "to 1/32, until no tetrahedron inverts; else the "
                      "step is cut back), 'secant' extrapolates them from "
                      "the last two converged loads (tangent where that "
                      "inverts a tetrahedron), 'join only' leaves them "
                      "where they are.");
    prm.declare_entry("Load path",
                      "rigid",
                      Patterns::Selection("rigid|linear"),
                      "'rigid': at a load s every moved bone is turned by s "
                      "times its angle and moved by s times its "
                      "translation, so it stays rigid on the way; "
                      "'linear': s times the final displacement, which "
                      "shrinks a turned bone on the way. Both end at the "
                      "planning.");
    prm.declare_entry("Indefinite tangent",
                      "cut back",
                      Patterns::Selection("cut back|lu|lu and unstable"),
                      "What a Newton iteration does when the tangent is not "
                      "positive definite: 'cut back' fails the step (halves "
                      "the increment); 'lu' solves it by UMFPACK's LU "
                      "factorisation (Newton's direction lowers the "
                      "residual norm without definiteness) and then accepts "
                      "the step's equilibrium only if its tangent is "
                      "positive definite (Cholesky), so that the answer is "
                      "stable; 'lu and unstable' accepts unstable "
                      "equilibria too (as CalculiX does; for comparison). "
                      "Measured (doc/results/nonlinear_solvers.md): 'lu' "
                      "reaches no further and costs an LU factorisation "
                      "each time, hence 'cut back'. Whatever the choice, "
                      "St. Venant-Kirchhoff's equilibria are tested for "
                      "stability at every load step (one Cholesky "
                      "factorisation), since CG may pass an indefinite "
                      "tangent unnoticed.");
    prm.declare_entry("Nonlinear solver",
                      "newton",
                      Patterns::Selection("newton|kinsol"),
                      "Who iterates after each load step's predictor: "
                      "'newton', softface's loop (full tangent every "
                      "iteration, backtracking on the residual norm), or "
                      "'kinsol', SUNDIALS' KINSOL (its line search; an "
                      "inverted trial state is a recoverable residual "
                      "error on a full step), with the same linear solver. "
                      "Not with contact or lips. With a Debug build of "
                      "deal.II 9.4 a KINSOL failure aborts (its return "
                      "code is checked by a debug assertion).");
  }

  void
  LoadSteppedNewton::Parameters::parse_parameters(ParameterHandler  &prm,
                                                  const std::string &model)
  {
    initial_increment            = prm.get_double("Initial load increment");
    minimum_increment            = prm.get_double("Minimum load increment");
    max_iterations               = prm.get_integer("Maximum Newton iterations");
    residual_tolerance           = prm.get_double("Residual tolerance");
    const std::string p          = prm.get("Predictor");
    predictor                    = p == "secant"    ? Predictor::secant :
                                   p == "join only" ? Predictor::join_only :
                                                      Predictor::tangent;
    rigid_path                   = prm.get("Load path") == "rigid";
    const std::string indefinite = prm.get("Indefinite tangent");
    indefinite_lu                = indefinite != "cut back";
    accept_unstable              = indefinite == "lu and unstable";
    corrector = prm.get("Nonlinear solver") == "kinsol" ? Corrector::kinsol :
                                                          Corrector::newton;
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

  void
  LoadSteppedNewton::set_path(const Path &p)
  {
    path = p;
  }

  void
  LoadSteppedNewton::set_initial_guess(const Vector<double> *guess)
  {
    initial_guess = guess;
  }

  const Vector<double> *
  LoadSteppedNewton::bone_now() const
  {
    return path && prm.rigid_path ? &bone_on_path : bone;
  }

  double
  LoadSteppedNewton::bone_factor(const double load) const
  {
    return path && prm.rigid_path ? 1. : load;
  }

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

  LoadSteppedNewton::StepState::StepState(const unsigned int n)
      : join_increment(n)
      , forces(n)
      , rhs(n)
      , du(n)
      , trial(n)
      , trial_forces(n)
  {}

  double
  LoadSteppedNewton::free_norm(const Vector<double> &v)
  {
    // What the holding constraints take up is not unbalanced.
    if (constraints == nullptr)
      return ConstrainedSystem::free_norm(is_join, v);
    condensed = v;
    constraints->condense(condensed);
    return ConstrainedSystem::free_norm(is_join, condensed);
  }

  std::string
  LoadSteppedNewton::refused(const std::string &what) const
  {
    return what + (where_refused ? where_refused() : std::string());
  }

  LoadSteppedNewton::StepResult
  LoadSteppedNewton::step(Vector<double>       &u,
                          const Vector<double> &target,
                          const double          load,
                          TimerOutput          &timer,
                          std::ostream         *progress,
                          const Vector<double> *guess)
  {
    const unsigned int n = u.size();
    StepResult         result;
    StepState          s(n);
    // The first iteration carries the join DoFs to the step's target.
    for (unsigned int i = 0; i < n; ++i)
      if (is_join[i])
        s.join_increment[i] = target[i] - u[i];

    // A start other than the tangent predictor: taken if the
    // discretisation accepts it, and Newton corrects from there.
    if (guess != nullptr)
      {
        if (start_from_guess(*guess, load, timer, u, s))
          {
            if (prm.corrector == Parameters::Corrector::kinsol)
              return kinsol_step(u, load, timer, result, false);
          }
        else if (prm.predictor == Parameters::Predictor::join_only)
          {
            result.reason = refused("the predictor inverts a tetrahedron");
            return result;
          }
        else
          ++report.secant_fallbacks;
      }
    for (unsigned int it = 0; it <= prm.max_iterations; ++it)
      {
        Timer              iteration_timer;
        const unsigned int linear_before = report.linear_iterations;
        // The tangent predictor: the iteration that moves the join DoFs.
        const bool first = (it == 0) && !s.evaluated;
        {
          TimerOutput::Scope scope(timer, "assembly");
          if (!s.evaluated && !unbalanced_forces(u, load, s.forces, &tangent))
            {
              result.reason = refused("a tetrahedron is inverted");
              return result;
            }
        }
        const double residual = free_norm(s.forces);
        result.residual       = residual / std::max(reference_force, 1e-300);
        if (it > 0 && residual <= prm.residual_tolerance * reference_force)
          return converged_if_stable(u, load, timer, s.indefinite, result);
        if (it == prm.max_iterations)
          break;

        assemble_newton_system(u, load, timer, s);
        if (first)
          {
            reference_force = std::max(reference_force, free_norm(s.rhs));
            if (reference_force == 0.)
              {
                // Nothing is unbalanced (e.g. every vertex is a join point):
                // the join DoFs still move.
                u += s.join_increment;
                result.converged = true;
                return result;
              }
          }
        if (!solve_newton_system(timer, s, result))
          return result;
        ++result.iterations;

        if (!line_search(u, load, first, residual, timer, s))
          {
            result.reason = first ?
                              refused("the predictor inverts a tetrahedron") :
                              "the line search found no descent";
            return result;
          }
        u.swap(s.trial);
        s.forces.swap(s.trial_forces);
        s.evaluated      = true;
        s.join_increment = 0.;
        if (prm.corrector == Parameters::Corrector::kinsol)
          return kinsol_step(u, load, timer, result, s.indefinite);
        report_slow_iteration(
          progress, iteration_timer, first, linear_before, result);
      }
    result.reason =
      "no convergence in " + std::to_string(prm.max_iterations) + " iterations";
    return result;
  }

  bool
  LoadSteppedNewton::start_from_guess(const Vector<double> &guess,
                                      const double          load,
                                      TimerOutput          &timer,
                                      Vector<double>       &u,
                                      StepState            &s)
  {
    bool valid;
    {
      TimerOutput::Scope scope(timer, "assembly");
      valid = unbalanced_forces(guess, load, s.forces, &tangent);
    }
    if (!valid)
      return false;
    u                = guess;
    s.evaluated      = true;
    s.join_increment = 0.;
    // The step's scale: what the start leaves unbalanced.
    reference_force = std::max(reference_force, free_norm(s.forces));
    return true;
  }

  LoadSteppedNewton::StepResult
  LoadSteppedNewton::converged_if_stable(const Vector<double> &u,
                                         const double          load,
                                         TimerOutput          &timer,
                                         const bool            indefinite,
                                         StepResult            result)
  {
    // An iteration crossed an indefinite tangent: keep the equilibrium
    // only if it is stable.
    if ((indefinite || prm.check_stability) && !prm.accept_unstable &&
        !tangent_positive_definite(u, load, timer))
      {
        result.reason   = "the equilibrium reached is unstable (its "
                          "tangent is not positive definite)";
        result.unstable = true;
        return result;
      }
    result.converged = true;
    return result;
  }

  void
  LoadSteppedNewton::assemble_newton_system(const Vector<double> &u,
                                            const double          load,
                                            TimerOutput          &timer,
                                            StepState            &s)
  {
    TimerOutput::Scope scope(timer, "assembly");
    if (distributed != nullptr)
      distributed->right_hand_side_and_eliminate(s.join_increment,
                                                 s.forces,
                                                 s.rhs);
    else
      {
        ConstrainedSystem::right_hand_side(
          tangent, is_join, s.join_increment, &s.forces, s.rhs);
        ConstrainedSystem::eliminate_join_dofs(is_join, tangent);
      }
    if (constraints != nullptr)
      {
        // du = closing + C x: C^T K C x = C^T (rhs - K closing).
        constraints->closing_increment(u,
                                       *bone_now(),
                                       bone_factor(load),
                                       s.closing);
        Vector<double> K_closing(u.size());
        tangent.vmult(K_closing, s.closing);
        s.rhs -= K_closing;
        constraints->condense(tangent);
        constraints->condense(s.rhs);
      }
  }

  bool
  LoadSteppedNewton::solve_newton_system(TimerOutput &timer,
                                         StepState   &s,
                                         StepResult  &result)
  {
    LinearSolver::Result solve;
    {
      TimerOutput::Scope scope(timer, "linear solves");
      solve = solve_tangent(s.rhs, s.du);
      s.indefinite |= solve.converged && solve.not_positive_definite;
    }
    if (solve.not_positive_definite && !solve.converged)
      result.reason = "the tangent is not positive definite";
    else if (solve.negative_curvature && !solve.converged)
      result.reason = "the tangent is not positive definite (CG found "
                      "negative curvature after " +
                      std::to_string(solve.iterations) + " iterations)";
    else if (!solve.converged)
      result.reason = linear_solver.parameters().method +
                      " did not converge (" + std::to_string(solve.iterations) +
                      " iterations)";
    if (!solve.converged)
      return false;
    if (constraints != nullptr)
      {
        constraints->lines().distribute(s.du);
        s.du += s.closing;
      }
    for (unsigned int i = 0; i < s.du.size(); ++i)
      if (is_join[i])
        s.du[i] = s.join_increment[i];
    return true;
  }

  bool
  LoadSteppedNewton::line_search(const Vector<double> &u,
                                 const double          load,
                                 const bool            first,
                                 const double          residual,
                                 TimerOutput          &timer,
                                 StepState            &s)
  {
    // Backtracking on the residual norm. The predictor moves the join DoFs
    // whole; if its state is refused, its free part is halved (damped)
    // until it is not: the join points' motion is the load step, the free
    // points' linear guess may overshoot (a rotation's linearisation
    // stretches), and Newton corrects either.
    for (double alpha = 1.; alpha > 1. / 64; alpha /= 2)
      {
        s.trial = u;
        s.trial.add(alpha, s.du);
        if (first)
          for (unsigned int i = 0; i < u.size(); ++i)
            if (is_join[i])
              s.trial[i] = u[i] + s.du[i];
        bool valid;
        {
          TimerOutput::Scope scope(timer, "assembly");
          valid = unbalanced_forces(s.trial, load, s.trial_forces, &tangent);
        }
        if (valid && (first || free_norm(s.trial_forces) <=
                                 (1. - 1e-4 * alpha) * residual))
          {
            if (first && alpha < 1.)
              ++report.damped_predictors;
            return true;
          }
      }
    return false;
  }

  void
  LoadSteppedNewton::report_slow_iteration(std::ostream      *progress,
                                           const Timer       &iteration_timer,
                                           const bool         first,
                                           const unsigned int linear_before,
                                           const StepResult  &result) const
  {
    // Large (quadratic reference) solves take minutes: say where they are
    // once an iteration is slow enough for anyone to wonder.
    if (progress == nullptr || iteration_timer.wall_time() <= 5.)
      return;
    std::ostringstream line;
    line << "        Newton iteration " << result.iterations << ": ";
    if (first)
      line << "predictor (join points moved), ";
    else
      line << "relative residual before " << std::setprecision(2)
           << result.residual << ", ";
    line << report.linear_iterations - linear_before << " linear iterations, "
         << std::fixed << std::setprecision(1) << iteration_timer.wall_time()
         << " s\n";
    *progress << line.str() << std::flush;
  }

  LoadSteppedNewton::StepResult
  LoadSteppedNewton::kinsol_step(Vector<double> &u,
                                 const double    load,
                                 TimerOutput    &timer,
                                 StepResult      result,
                                 const bool      indefinite_predictor)
  {
    const unsigned int n      = u.size();
    unsigned int       n_free = 0;
    for (unsigned int i = 0; i < n; ++i)
      n_free += !is_join[i];
    // KINSOL stops on the max norm of the scaled residual; scaled by the
    // step's reference force and the number of free DoFs, that bounds the
    // same relative 2-norm as softface's loop.
    Vector<double> function_scaling(n);
    function_scaling = 1. / std::max(reference_force, 1e-300);
    using KINSOL     = SUNDIALS::KINSOL<Vector<double>>;
    KINSOL::AdditionalData data(KINSOL::AdditionalData::linesearch,
                                prm.max_iterations,
                                prm.residual_tolerance /
                                  std::sqrt(double(std::max(n_free, 1u))),
                                1e-14,
                                false,
                                1); // the exact tangent every iteration
    KINSOL                 kinsol(data);
    LinearSolver::Result   last_solve;
    bool                   refused    = false;
    bool                   indefinite = indefinite_predictor;
    kinsol.reinit_vector              = [n](Vector<double> &v) { v.reinit(n); };
    kinsol.residual = [&](const Vector<double> &x, Vector<double> &F) {
      TimerOutput::Scope scope(timer, "assembly");
      if (!unbalanced_forces(x, load, F, nullptr))
        {
          refused = true;
          return 1; // recoverable: KINSOL shortens the step
        }
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          F[i] = 0.;
      return 0;
    };
    kinsol.setup_jacobian = [&](const Vector<double> &x,
                                const Vector<double> &) {
      TimerOutput::Scope scope(timer, "assembly");
      Vector<double>     F(n);
      if (!unbalanced_forces(x, load, F, &tangent))
        return 1;
      ConstrainedSystem::eliminate_join_dofs(is_join, tangent);
      return 0;
    };
    kinsol.solve_with_jacobian =
      [&](const Vector<double> &rhs, Vector<double> &dst, const double) {
        TimerOutput::Scope scope(timer, "linear solves");
        last_solve = solve_tangent(rhs, dst);
        indefinite |= last_solve.converged && last_solve.not_positive_definite;
        for (unsigned int i = 0; i < n; ++i)
          if (is_join[i])
            dst[i] = 0.;
        return last_solve.converged ? 0 : -1;
      };
    kinsol.get_function_scaling = [&]() -> Vector<double> & {
      return function_scaling;
    };
    Vector<double> x = u;
    try
      {
        result.iterations += kinsol.solve(x);
      }
    catch (const std::exception &)
      {
        // deal.II 9.4 checks KINSOL's return code only in Debug builds (and
        // aborts there); the state left in x is judged below either way.
      }
    Vector<double> forces(n);
    const bool     valid = unbalanced_forces(x, load, forces, nullptr);
    result.residual      = ConstrainedSystem::free_norm(is_join, forces) /
                      std::max(reference_force, 1e-300);
    result.converged = valid && result.residual <= prm.residual_tolerance;
    if (!result.converged)
      {
        result.reason = "KINSOL stopped above the residual tolerance";
        if (!last_solve.converged && last_solve.iterations > 0)
          result.reason += " (a linear solve failed)";
        else if (refused)
          result.reason += " (trial states inverted a tetrahedron" +
                           (where_refused ? where_refused() : "") + ")";
      }
    else if ((indefinite || prm.check_stability) && !prm.accept_unstable &&
             !tangent_positive_definite(x, load, timer))
      {
        result.converged = false;
        result.unstable  = true;
        result.reason    = "the equilibrium reached is unstable (its tangent "
                           "is not positive definite)";
      }
    if (valid)
      u = x;
    return result;
  }

  LinearSolver::Result
  LoadSteppedNewton::solve_tangent(const Vector<double> &rhs,
                                   Vector<double>       &du)
  {
    if (distributed != nullptr)
      {
        const unsigned int builds_before = distributed->n_amg_builds();
        const auto         solve         = distributed->solve(rhs, du);
        report.linear_iterations += solve.iterations;
        report.amg_rebuilds += distributed->n_amg_builds() - builds_before;
        return solve;
      }
    const unsigned int   builds_before = linear_solver.n_amg_builds();
    LinearSolver::Result solve;
    du = 0.;
    if (linear_solver.set_matrix(tangent))
      solve = linear_solver.solve(rhs, du);
    else
      {
        solve.not_positive_definite = true;
        solve.iterations            = 1;
      }
    report.linear_iterations += solve.iterations;
    report.amg_rebuilds += linear_solver.n_amg_builds() - builds_before;
    if ((solve.not_positive_definite || solve.negative_curvature) &&
        prm.indefinite_lu)
      {
        // Newton's direction needs no definiteness: -K^{-1} r lowers |r|
        // for any invertible K. LU, refactorised each time (rare).
        SparseDirectUMFPACK lu;
        try
          {
            lu.initialize(tangent);
            lu.vmult(du, rhs);
          }
        catch (const std::exception &)
          {
            return solve; // singular: the step fails as before
          }
        ++report.indefinite_solves;
        solve.converged             = true;
        solve.not_positive_definite = true;
        solve.negative_curvature    = false;
      }
    return solve;
  }

  bool
  LoadSteppedNewton::tangent_positive_definite(const Vector<double> &u,
                                               const double          load,
                                               TimerOutput          &timer)
  {
    TimerOutput::Scope scope(timer, "stability checks");
    const unsigned int n = u.size();
    Vector<double>     forces(n);
    if (!unbalanced_forces(u, load, forces, &tangent))
      return false;
    ConstrainedSystem::eliminate_join_dofs(is_join, tangent);
    if (constraints != nullptr)
      constraints->condense(tangent);
    // Cholesky, whatever the linear solver: CG may converge on an
    // indefinite matrix without meeting negative curvature. The ordering
    // is computed once.
    return stability_cholesky.refactorize(tangent);
  }

  std::string
  LoadSteppedNewton::diagnose_tangent(const Vector<double> &u,
                                      const double          load,
                                      const double          next,
                                      const bool            unstable_next,
                                      TimerOutput          &timer)
  {
    if (load == 0.)
      return "";
    // The stability test is a Cholesky factorisation of the whole tangent.
    if (distributed != nullptr)
      return " (On several MPI ranks the tangent's stability is not "
             "tested: a run on one rank says whether the law lost stability "
             "there.)";
    std::ostringstream s;
    if (!tangent_positive_definite(u, load, timer))
      s << " At that load the tangent is not positive definite: the "
           "equilibrium is at a limit of stability of the material law.";
    else if (unstable_next)
      s << " At that load the equilibrium is stable (tangent positive "
           "definite); at "
        << next
        << " the equilibrium Newton found is unstable: the material law "
           "loses stability (a limit or bifurcation point) in between, "
           "so no smaller load step gets further along this branch "
           "('Indefinite tangent = lu and unstable' follows unstable "
           "equilibria, as CalculiX does).";
    else
      s << " At that load the equilibrium is stable (tangent positive "
           "definite; no limit of the law found): the next load step "
           "failed for the reason above.";
    return s.str();
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

  void
  LoadSteppedNewton::set_distributed_tangent(DistributedTangent *tangent_in)
  {
    distributed = tangent_in;
  }

  void
  LoadSteppedNewton::refuse_unsupported(const std::string &description) const
  {
    if (prm.corrector == Parameters::Corrector::kinsol &&
        constraints != nullptr)
      throw Error(description +
                  ": 'Nonlinear solver = kinsol' does not take the "
                  "constraints of sliding contact or separated lips; use "
                  "'newton'.");
    // What needs the whole tangent on one rank (the model runs whole on
    // every rank instead).
    AssertThrow(distributed == nullptr ||
                  (prm.corrector == Parameters::Corrector::newton &&
                   constraints == nullptr && !prm.indefinite_lu &&
                   !prm.check_stability),
                ExcMessage("Not on a distributed tangent."));
  }

  const Vector<double> *
  LoadSteppedNewton::predicted_start(const Vector<double> &u,
                                     const Vector<double> &target,
                                     const double          load,
                                     const double          next,
                                     const bool            from_guess,
                                     Vector<double>       &guess) const
  {
    const unsigned int n = u.size();
    if (from_guess)
      guess = *initial_guess;
    else if (prm.predictor == Parameters::Predictor::join_only)
      guess = u;
    else if (prm.predictor == Parameters::Predictor::secant &&
             previous.size() == n)
      {
        guess = u;
        guess.sadd(1. + (next - load) / (load - previous_load),
                   -(next - load) / (load - previous_load),
                   previous);
      }
    else
      return nullptr;
    for (unsigned int i = 0; i < n; ++i)
      if (is_join[i])
        guess[i] = target[i];
    return &guess;
  }

  void
  LoadSteppedNewton::settle_active_set(
    const Vector<double>              &u,
    const double                       load,
    const std::function<StepResult()> &step_again,
    StepResult                        &result)
  {
    // Unilateral constraints: release those that pull, hold those passed
    // through, and solve the step again until none changes.
    for (unsigned int round = 1; result.converged && constraints != nullptr &&
                                 constraints->has_unilateral();
         ++round)
      {
        Vector<double> forces(u.size());
        unbalanced_forces(u, load, forces, nullptr);
        if (constraints->update_active_set(
              u, *bone_now(), forces, bone_factor(load)) == 0)
          return;
        if (round == max_rounds)
          {
            result.converged = false;
            result.reason    = "the contact's active set still changed "
                               "after " +
                            std::to_string(max_rounds) +
                            " solves ('Maximum active-set iterations')";
            return;
          }
        const unsigned int before = result.iterations;
        result                    = step_again();
        result.iterations += before;
      }
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
    refuse_unsupported(description);
    external             = external_forces;
    const unsigned int n = join_motion.size();
    report               = Report();
    reference_force      = 0.;
    u.reinit(n);
    Vector<double> converged = u, target(n);
    previous.reinit(0);
    previous_load = 0.;
    Vector<double> guess;
    double         load = 0., increment = prm.initial_increment;
    while (load < 1.)
      {
        const double next = std::min(1., load + increment);
        if (path && prm.rigid_path)
          path(next, target, bone_on_path);
        else
          target.equ(next, join_motion);
        // A first step to the full load starts from the guess, if any.
        const bool from_guess = initial_guess != nullptr &&
                                initial_guess->size() == n && load == 0. &&
                                next == 1. && report.cutbacks == 0;
        const Vector<double> *start =
          predicted_start(u, target, load, next, from_guess, guess);
        StepResult result = step(u, target, next, timer, progress, start);
        settle_active_set(
          u,
          next,
          [&]() { return step(u, target, next, timer, progress); },
          result);
        if (result.converged)
          {
            report.started_from_guess |= from_guess;
            if (prm.predictor == Parameters::Predictor::secant)
              {
                previous      = converged;
                previous_load = load;
              }
            load                = next;
            converged           = u;
            report.load_reached = load;
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
                  << " cut-backs. Last converged load: " << load << "."
                  << diagnose_tangent(u, load, next, result.unstable, timer)
                  << hint;
                throw Error(m.str());
              }
          }
      }
    return report;
  }
} // namespace softface

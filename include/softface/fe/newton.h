#ifndef softface_fe_newton_h
#define softface_fe_newton_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <softface/fe/distributed_tangent.h>
#include <softface/fe/linear_solver.h>
#include <softface/fe/sparse_cholesky.h>
#include <softface/fe/vertex_constraints.h>

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Newton's method with load stepping for a discretisation whose join DoFs
   * are prescribed (the nonlinear FEM models). The join DoFs' motion is
   * applied in load steps, along a path the model gives (each bone rigid at
   * every load) or scaled linearly; each step is solved by Newton's method
   * with the consistent tangent, every update line-searched on the residual
   * norm and refused if the discretisation refuses the state (an inverted
   * element).
   *
   * Each step starts from a predictor that moves the join DoFs to the
   * step's target:
   * - tangent (default): the free DoFs follow linearly (the tangent system
   *   solved for the join increment); if that state is refused, the free
   *   part is halved until it is not (a damped predictor);
   * - secant: the free DoFs extrapolated from the last two converged loads
   *   (the tangent predictor where there is no such pair or the state is
   *   refused);
   * - join only: the free DoFs stay (the naive predictor, for comparison).
   * A tangent that is not positive definite fails the step or, if asked,
   * is solved by LU (Newton's direction needs no definiteness); an
   * equilibrium reached through one, and every St. Venant-Kirchhoff
   * equilibrium, is accepted only if its tangent is positive definite (a
   * stable equilibrium), unless the user asks for unstable ones too. A
   * step that fails (refused state, no descent, no convergence, an
   * indefinite tangent, an unstable equilibrium) is retried with half the
   * increment; a step that converges in at most four iterations lets
   * the next one grow. When the increment falls below its minimum, the
   * error says how far the solve got and whether the law lost stability
   * there.
   *
   * The corrector after the predictor is this class's loop (default) or
   * SUNDIALS' KINSOL. On the off-centre cases
   * (doc/results/nonlinear_solvers.md): KINSOL gives the same answers and
   * loads in about as many iterations and as much time, so the loop, which
   * reports why a step failed and works with contact constraints, stays
   * the default; the tangent predictor needs far fewer iterations than
   * leaving the free points (join only), and the secant one is no better;
   * the rigid path keeps bones rigid on the way at no cost; LU on an
   * indefinite tangent saves a cut-back now and then but reaches no
   * further and costs a factorisation, so cutting back stays the default.
   */
  class LoadSteppedNewton
  {
  public:
    struct Parameters
    {
      double       initial_increment  = 1.;
      double       minimum_increment  = 1e-3;
      unsigned int max_iterations     = 20;
      double       residual_tolerance = 1e-10;
      enum class Predictor
      {
        tangent,
        secant,
        join_only
      };
      Predictor predictor = Predictor::tangent;
      /// Follow the model's load path (rigid bones), if it gives one.
      bool rigid_path = true;
      /// Who corrects after the predictor: this class's Newton loop or
      /// SUNDIALS' KINSOL (line search; a refused state is a recoverable
      /// error of the residual).
      enum class Corrector
      {
        newton,
        kinsol
      };
      Corrector corrector = Corrector::newton;
      /// Solve an indefinite tangent by LU (else the step fails).
      bool indefinite_lu = false;
      /// Accept an equilibrium whose tangent is not positive definite.
      bool accept_unstable = false;
      /// Test every load step's equilibrium for stability (Cholesky of its
      /// tangent), not only those reached through an indefinite tangent:
      /// set by the model for a law that loses stability under compression
      /// (St. Venant-Kirchhoff), since CG can pass an indefinite tangent
      /// unnoticed.
      bool check_stability = false;

      static void
      declare_parameters(ParameterHandler &prm);
      /// Throws a clear error for values that would never end a solve.
      void
      parse_parameters(ParameterHandler &prm, const std::string &model);
    };

    /**
     * The discretisation: internal nodal forces at @p u and, if @p tangent is
     * not null, the unconstrained tangent assembled into it. Returns false if
     * the state is refused (an inverted element).
     */
    using Evaluate = std::function<bool(const Vector<double> &u,
                                        Vector<double>       &forces,
                                        SparseMatrix<double> *tangent)>;

    struct Report
    {
      unsigned int load_steps = 0;
      unsigned int cutbacks   = 0;
      /// Predictors whose free part was halved until the state was valid.
      unsigned int damped_predictors = 0;
      /// Secant predictors refused (an inverted element): tangent instead.
      unsigned int secant_fallbacks = 0;
      double       load_reached     = 0.;
      /// Newton systems whose tangent was not positive definite, solved
      /// by LU ('Indefinite tangent = lu').
      unsigned int              indefinite_solves = 0;
      unsigned int              newton_iterations = 0;
      unsigned int              linear_iterations = 0;
      unsigned int              amg_rebuilds      = 0;
      double                    final_residual    = 0.; ///< relative
      std::vector<unsigned int> iterations_per_step;
      /// The first load step converged from the initial guess.
      bool started_from_guess = false;
    };

    /// @p where_refused, if given, says where the last refused state was
    /// refused (e.g. " (cell 12 at (1, 2, 3))"), for the failure reasons.
    LoadSteppedNewton(const Parameters                   &parameters,
                      const Evaluate                     &evaluate,
                      SparseMatrix<double>               &tangent,
                      const std::vector<bool>            &is_join,
                      LinearSolver                       &linear_solver,
                      const std::function<std::string()> &where_refused = {});

    /**
     * Solve subject to @p constraints (sliding contact, the lips' contact)
     * too, with the bone displacement at sliding vertices in @p bone (both
     * referenced until solve() returns). Each Newton step's increment keeps
     * the holding constraints (closing their gaps at the step's load); the
     * residual is measured in the constrained directions; after a load step
     * converges, unilateral ones are updated and the step repeated until
     * none changes (at most @p max_active_set_rounds times, else the step
     * fails and is cut back).
     */
    void
    set_vertex_constraints(VertexConstraintSet  *constraints,
                           const Vector<double> *bone,
                           const unsigned int    max_active_set_rounds);

    /// The report of the solve running or last ended (also one that
    /// threw).
    const Report &
    report_so_far() const
    {
      return report;
    }

    /**
     * Assemble, eliminate and solve the tangent on several MPI ranks through
     * @p tangent (referenced until solve() returns; null: the serial tangent
     * and linear solver). The evaluation then fills @p tangent where it is
     * asked for the tangent (the serial matrix's pointer says only whether).
     * Newton's vectors stay whole on every rank, so every rank decides
     * alike. Not with KINSOL, vertex constraints, LU on an indefinite
     * tangent or the stability test (they need the whole tangent).
     */
    void
    set_distributed_tangent(DistributedTangent *tangent);

    /**
     * The join DoFs' target at a load in (0, 1] and, with vertex
     * constraints, the bone displacement at the sliding vertices there,
     * instead of the load times the final ones. Used if
     * Parameters::rigid_path.
     */
    using Path = std::function<void(const double    load,
                                    Vector<double> &join_target,
                                    Vector<double> &bone)>;
    void
    set_path(const Path &path);

    /**
     * Start the first load step, if it goes to the full load, from
     * @p guess (e.g. a linear model's answer to the same plan; its join DoFs
     * are replaced by the target) instead of the predictor; nullptr: none.
     * Referenced until solve() returns. A guess the discretisation refuses
     * falls back to the tangent predictor.
     */
    void
    set_initial_guess(const Vector<double> *guess);

    /**
     * Carry @p u (zero on entry) to equilibrium with its join DoFs at
     * @p join_motion and, if not null, the external nodal forces
     * @p external_forces (gravity), both applied in the same load steps. Phases
     * go to @p timer ("assembly", "linear solves"), a line per load step to @p
     * progress if not null. On failure throws an Error that starts with @p
     * description (e.g. "nonlinear fem (neo-hooke, cg amg)"), gives the load
     * step, load, residual and reason, and ends with @p hint.
     */
    Report
    solve(const Vector<double> &join_motion,
          Vector<double>       &u,
          TimerOutput          &timer,
          std::ostream         *progress,
          const std::string    &description,
          const std::string    &hint,
          const Vector<double> *external_forces = nullptr);

  private:
    struct StepResult
    {
      bool         converged  = false;
      unsigned int iterations = 0;
      double       residual   = 0.;
      std::string  reason;
      /// The step converged to an equilibrium that is not stable.
      bool unstable = false;
    };

    /// Newton's vectors within a load step.
    struct StepState
    {
      explicit StepState(const unsigned int n);
      /// The join DoFs' motion still to make: the step's, until the first
      /// accepted iteration, then zero.
      Vector<double> join_increment;
      Vector<double> forces, rhs, du, trial, trial_forces;
      /// The part of the increment that closes the holding constraints'
      /// gaps.
      Vector<double> closing;
      /// The accepted line-search point was evaluated with its tangent, so
      /// the next iteration starts from it without assembling again.
      bool evaluated = false;
      /// Whether an iteration solved with an indefinite tangent (LU).
      bool indefinite = false;
    };

    /// @p guess, if not null, is a start for the step with its join DoFs
    /// at @p target (the secant or join-only predictor); if the
    /// discretisation refuses it, the tangent predictor runs instead
    /// (join only: the step fails).
    StepResult
    step(Vector<double>       &u,
         const Vector<double> &target,
         const double          load,
         TimerOutput          &timer,
         std::ostream         *progress,
         const Vector<double> *guess = nullptr);

    /// Take @p guess as the step's start if the discretisation accepts it
    /// (u, forces and tangent there); false if it refuses it.
    bool
    start_from_guess(const Vector<double> &guess,
                     const double          load,
                     TimerOutput          &timer,
                     Vector<double>       &u,
                     StepState            &s);

    /// @p result converged at @p u, unless an iteration crossed an
    /// indefinite tangent (or Parameters::check_stability) and the tangent
    /// there is not positive definite.
    StepResult
    converged_if_stable(const Vector<double> &u,
                        const double          load,
                        TimerOutput          &timer,
                        const bool            indefinite,
                        StepResult            result);

    /// The Newton system at @p u from the forces and tangent there: the
    /// right-hand side with the join increment, the join DoFs eliminated,
    /// the holding constraints condensed.
    void
    assemble_newton_system(const Vector<double> &u,
                           const double          load,
                           TimerOutput          &timer,
                           StepState            &s);

    /// The increment s.du, with its join and constrained parts; false, with
    /// the reason in @p result, if the linear solver failed.
    bool
    solve_newton_system(TimerOutput &timer, StepState &s, StepResult &result);

    /// Backtracking along s.du from @p u; true if a point is accepted (in
    /// s.trial, its forces and tangent evaluated).
    bool
    line_search(const Vector<double> &u,
                const double          load,
                const bool            first,
                const double          residual,
                TimerOutput          &timer,
                StepState            &s);

    /// A progress line for an iteration that took over 5 s.
    void
    report_slow_iteration(std::ostream      *progress,
                          const Timer       &iteration_timer,
                          const bool         first,
                          const unsigned int linear_before,
                          const StepResult  &result) const;

    /// The norm of @p v on the free DoFs, in the constrained directions.
    double
    free_norm(const Vector<double> &v);

    /// @p what, followed by where the discretisation refused a state.
    std::string
    refused(const std::string &what) const;

    /// Throw if the solver's parameters and the tangent's layout do not go
    /// together (KINSOL with constraints; what needs the whole tangent).
    void
    refuse_unsupported(const std::string &description) const;

    /// The start of the step from @p load to @p next in @p guess (join
    /// DoFs at @p target): the initial guess if @p from_guess, else the
    /// predictor's if it is not the tangent's; nullptr: the tangent
    /// predictor.
    const Vector<double> *
    predicted_start(const Vector<double> &u,
                    const Vector<double> &target,
                    const double          load,
                    const double          next,
                    const bool            from_guess,
                    Vector<double>       &guess) const;

    /// After a converged step to @p load: update the unilateral constraints
    /// and solve the step again (@p step_again) until none changes
    /// (@p result then is the last solve's, its iterations summed).
    void
    settle_active_set(const Vector<double>              &u,
                      const double                       load,
                      const std::function<StepResult()> &step_again,
                      StepResult                        &result);

    /// The corrector iterations of a step by KINSOL, from @p u (the
    /// predictor's state, join DoFs at the step's target).
    /// @p indefinite_predictor: the predictor solved an indefinite
    /// tangent (the equilibrium must then be tested for stability).
    StepResult
    kinsol_step(Vector<double> &u,
                const double    load,
                TimerOutput    &timer,
                StepResult      result,
                const bool      indefinite_predictor);

    /// The Newton system with the current tangent (eliminated and
    /// condensed); an indefinite one by LU if Parameters::indefinite_lu
    /// (then converged and not_positive_definite are both set).
    LinearSolver::Result
    solve_tangent(const Vector<double> &rhs, Vector<double> &du);

    /// Whether the tangent at @p u is positive definite on the free DoFs
    /// (false also if the state is refused). Overwrites the tangent.
    bool
    tangent_positive_definite(const Vector<double> &u,
                              const double          load,
                              TimerOutput          &timer);

    /// What stopped the solve, for the failure message: the tangent at
    /// @p u (converged at @p load), and whether the step to @p next found
    /// only an unstable equilibrium.
    std::string
    diagnose_tangent(const Vector<double> &u,
                     const double          load,
                     const double          next,
                     const bool            unstable_next,
                     TimerOutput          &timer);

    const Parameters                   prm;
    const Evaluate                     evaluate;
    SparseMatrix<double>              &tangent;
    const std::vector<bool>           &is_join;
    LinearSolver                      &linear_solver;
    const std::function<std::string()> where_refused;

    /// Internal forces minus the external ones at @p load.
    bool
    unbalanced_forces(const Vector<double> &u,
                      const double          load,
                      Vector<double>       &forces,
                      SparseMatrix<double> *tangent) const;

    Report report;
    /// The largest unbalanced force a load step started with.
    double reference_force = 0.;
    /// The converged state before the last one and its load, for the
    /// secant predictor.
    Vector<double>        previous;
    double                previous_load = 0.;
    const Vector<double> *external      = nullptr;
    VertexConstraintSet  *constraints   = nullptr;
    const Vector<double> *bone          = nullptr;
    unsigned int          max_rounds    = 50;
    Path                  path;
    const Vector<double> *initial_guess = nullptr;
    DistributedTangent   *distributed   = nullptr;
    /// For the stability checks (its ordering reused).
    SparseCholesky stability_cholesky;
    /// The bone displacement at the current load on a path, and the load
    /// factor the constraints apply to the bone vector (1 on a path).
    Vector<double> bone_on_path;
    /// Scratch for free_norm().
    Vector<double> condensed;
    const Vector<double> *
    bone_now() const;
    double
    bone_factor(const double load) const;
  };
} // namespace softface

#endif

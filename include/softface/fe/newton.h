#ifndef softface_fe_newton_h
#define softface_fe_newton_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <softface/fe/linear_solver.h>
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
   * applied in load steps; each step is solved by Newton's method with the
   * consistent tangent: the first iteration moves the join DoFs to the
   * step's target and predicts the free ones linearly, later ones correct
   * with the join DoFs fixed. Every update is line-searched on the residual
   * norm and refused if the discretisation refuses the state (an inverted
   * element). A step that fails (refused state, no descent, no convergence,
   * a tangent that is not positive definite) is retried with half the
   * increment; a step that converges in at most four iterations lets the
   * next one grow.
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
      unsigned int              load_steps        = 0;
      unsigned int              cutbacks          = 0;
      unsigned int              newton_iterations = 0;
      unsigned int              linear_iterations = 0;
      unsigned int              amg_rebuilds      = 0;
      double                    final_residual    = 0.; ///< relative
      std::vector<unsigned int> iterations_per_step;
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
    };

    StepResult
    step(Vector<double>       &u,
         const Vector<double> &target,
         const double          load,
         TimerOutput          &timer,
         std::ostream         *progress);

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
    double                reference_force = 0.;
    const Vector<double> *external        = nullptr;
    VertexConstraintSet  *constraints     = nullptr;
    const Vector<double> *bone            = nullptr;
    unsigned int          max_rounds      = 50;
  };
} // namespace softface

#endif

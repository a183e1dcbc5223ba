#ifndef softface_fe_vertex_constraints_h
#define softface_fe_vertex_constraints_h

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/fe/linear_solver.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The scene's constraints on free vertices (SceneEffects::
   * vertex_constraints: sliding contact with the bone, the lips' contact)
   * for the FEM models, as deal.II AffineConstraints on the shared layout:
   * each holding constraint n . (u_a - u_b) = g makes the component of a
   * with the largest |n_i| a combination of the other DoFs of a and b.
   * Matrices are condensed with the homogeneous lines (C^T K C, the same
   * for every planning); a constraint's g, and any defect of the current
   * iterate, enter through the right-hand side. Unilateral constraints hold
   * or not by an active-set iteration: one that pulls (a negative contact
   * pressure) is released, one that is passed through is made to hold.
   */
  class VertexConstraintSet
  {
  public:
    explicit VertexConstraintSet(const Scene &scene);

    unsigned int
    size() const;

    /// Which constraints hold now (all, at the start).
    const std::vector<bool> &
    holding() const;
    unsigned int
    n_holding() const;

    /**
     * n . (u_a - u_b) - load * g at displacement @p u, where g comes from
     * @p prescribed (the bone's displacement at a sliding vertex).
     */
    double
    gap(const unsigned int    c,
        const Vector<double> &u,
        const Vector<double> &prescribed,
        const double          load = 1.) const;

    /**
     * Add to @p dsp (a layout's couplings) the entries that condensing with
     * any subset of the constraints holding needs: a slave's row and column
     * to its masters, and the masters of two coupled slaves to each other.
     */
    void
    add_fill(DynamicSparsityPattern &dsp) const;

    /// The homogeneous lines of the holding constraints.
    const AffineConstraints<double> &
    lines() const;

    /**
     * The correction that closes the holding constraints' gaps at @p u:
     * -gap / n_i on each slave DoF, zero elsewhere.
     */
    void
    closing_increment(const Vector<double> &u,
                      const Vector<double> &prescribed,
                      const double          load,
                      Vector<double>       &increment) const;

    /**
     * Solve K_e du = rhs subject to the holding constraints, with du equal
     * to @p closing on the slave DoFs' inhomogeneous part: K_e is the
     * join-eliminated matrix, @p condensed its copy condensed with lines()
     * (which @p solver has been given), @p rhs the join-eliminated
     * right-hand side. @p du holds the answer (zero on the join DoFs).
     */
    LinearSolver::Result
    solve(const SparseMatrix<double> &eliminated,
          LinearSolver               &solver,
          const Vector<double>       &closing,
          const Vector<double>       &rhs,
          Vector<double>             &du) const;

    /**
     * Condense @p eliminated (the join-eliminated matrix, on a sparsity
     * with the constraints' fill) into @p condensed for the holding
     * constraints and give it to @p solver, unless @p condensed_for says it
     * is condensed for them already. Throws an error naming @p model if a
     * direct factorisation fails.
     */
    void
    condense_for_holding(const SparseMatrix<double> &eliminated,
                         SparseMatrix<double>       &condensed,
                         std::vector<bool>          &condensed_for,
                         LinearSolver               &solver,
                         const std::string          &model) const;

    struct ActiveSetReport
    {
      LinearSolver::Result result;
      unsigned int         rounds = 0;
    };

    /**
     * The linear models' solve (linear FEM, the mass tensor model's
     * converged answer): K u = f with the join DoFs at @p prescribed and
     * the constraints, unilateral ones by the active-set iteration.
     * @p unconstrained is K, @p eliminated K with the join DoFs eliminated,
     * @p rhs its right-hand side (ConstrainedSystem::right_hand_side),
     * @p minus_forces -f (null: no load). Throws an error naming @p model
     * when the active set still changes after @p max_rounds solves.
     */
    ActiveSetReport
    solve_with_active_set(const SparseMatrix<double> &unconstrained,
                          const SparseMatrix<double> &eliminated,
                          SparseMatrix<double>       &condensed,
                          std::vector<bool>          &condensed_for,
                          LinearSolver               &solver,
                          const Vector<double>       &rhs,
                          const Vector<double>       &prescribed,
                          const Vector<double>       *minus_forces,
                          const unsigned int          max_rounds,
                          const std::string          &model,
                          Vector<double>             &u);

    /**
     * C^T K C in place for the holding constraints (@p matrix on a sparsity
     * with their fill). A slave row keeps its own diagonal entry, as an
     * eliminated join DoF does: ML built on the matrix then stays a
     * positive definite preconditioner (with deal.II's average diagonal
     * it was not, and CG met negative curvature).
     */
    void
    condense(SparseMatrix<double> &matrix) const;

    /// The holding constraints' lines applied to @p v: C^T v (slave
    /// entries moved to their masters and zeroed).
    void
    condense(Vector<double> &v) const;

    /**
     * Update which unilateral constraints hold, given the displacement and
     * the unbalanced nodal forces (K u - f: the constraint forces at the
     * constrained vertices). Returns how many changed.
     */
    unsigned int
    update_active_set(const Vector<double> &u,
                      const Vector<double> &prescribed,
                      const Vector<double> &unbalanced,
                      const double          load = 1.);

    /// True if some constraint is unilateral (an active-set iteration).
    bool
    has_unilateral() const;

    /// A line for details: "holding 12 of 40".
    std::string
    describe() const;

  private:
    void
    build_lines();
    void
    make_lines(const std::vector<bool>   &holding,
               AffineConstraints<double> &lines) const;

    struct Line
    {
      std::array<types::global_dof_index, 3> a, b; // b invalid: no partner
      Tensor<1, 3>                           n;
      bool                                   partnered;
      bool                                   unilateral;
      unsigned int                           slave; // 0..2: component of a
    };
    std::vector<Line>         constraint_lines;
    std::vector<bool>         is_holding;
    AffineConstraints<double> homogeneous;
    unsigned int              n_dofs;
  };
} // namespace softface

#endif

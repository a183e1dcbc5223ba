#ifndef softface_fe_distributed_tangent_h
#define softface_fe_distributed_tangent_h

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <softface/core/distributed_layout.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/linear_solver.h>

#include <array>
#include <memory>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The Newton tangent and nodal forces of a P1 nonlinear FEM model on a
   * DistributedLayout (issue 20). The model evaluates the cells at this
   * rank's DoFs (add_cell()); the tangent stays a Trilinos matrix on the
   * ranks, the forces come back as the serial vector on every rank.
   *
   * LoadSteppedNewton keeps its vectors whole on every rank, in the serial
   * layout: they are a small part of a run's memory (the matrix and its ML
   * are most of it), and every rank computing the same norms from the same
   * numbers makes the same decision (line search, load step, cut-back)
   * without a reduction of its own. What a rank does alone is its cells'
   * assembly, its rows of the matrix and its part of each CG iteration.
   *
   * The linear solves are CG with ML (the serial model's parameters and the
   * six rigid-body modes), built on the first tangent given to build_amg()
   * and rebuilt as the serial LinearSolver rebuilds it (a solve over 'AMG
   * rebuild iterations' rebuilds it for the next ones, one still running at
   * twice that many continues with ML rebuilt at once).
   */
  class DistributedTangent
  {
  public:
    /// Set up the unconstrained sparsity of the layout. Collective.
    DistributedTangent(const DistributedLayout        &layout,
                       const LinearSolver::Parameters &parameters);

    /**
     * The cells this rank evaluates, by their layout DoFs (vertex by vertex,
     * component by component): its own cells and the ghost cells at the DoFs
     * it owns. Each cell adds to the rows this rank owns only, so that no
     * contribution crosses the ranks; a cell at two ranks' DoFs is
     * evaluated on both. The matrix positions of every cell's entries are
     * found here once, as the serial model finds them.
     */
    void
    set_cells(
      const std::vector<std::array<types::global_dof_index, 12>> &cell_dofs);

    /// Zero the forces and, if @p with_tangent, the tangent.
    void
    begin_assembly(const bool with_tangent);

    /// Add the forces and, if the assembly has one, the tangent of cell
    /// @p cell (its place in set_cells()) on this rank's rows.
    void
    add_cell(const unsigned int cell, const Elasticity::P1Response &response);

    /// The forces in the serial layout on every rank. Collective.
    void
    end_assembly(Vector<double> &forces);

    /**
     * As ConstrainedSystem::right_hand_side() and eliminate_join_dofs() on
     * the serial tangent: @p rhs (serial layout) is -(K d + r) on the free
     * rows and |K_jj| d_j on the join rows for the join increment @p d and
     * the residual @p r, then the join DoFs' rows and columns leave the
     * tangent, their diagonal's magnitude kept. Collective.
     */
    void
    right_hand_side_and_eliminate(const Vector<double> &join_increment,
                                  const Vector<double> &residual,
                                  Vector<double>       &rhs);

    /// Build ML on the tangent as it is (eliminated). Collective.
    void
    build_amg();

    /// Solve the eliminated tangent for @p rhs (serial layout, on every
    /// rank) from zero; @p du is the answer on every rank. Collective.
    LinearSolver::Result
    solve(const Vector<double> &rhs, Vector<double> &du);

    unsigned int
    n_amg_builds() const;

  private:
    /// One CG run of at most @p limit iterations from @p solution.
    bool
    iterate(const TrilinosWrappers::MPI::Vector &rhs,
            TrilinosWrappers::MPI::Vector       &solution,
            const double                         tolerance,
            const unsigned int                   limit,
            LinearSolver::Result                &result);

    const DistributedLayout       &layout;
    const LinearSolver::Parameters parameters;
    TrilinosWrappers::SparseMatrix tangent;
    /// The tangent ML was built on (ML refers to it).
    TrilinosWrappers::SparseMatrix amg_matrix;
    /// The owned entries.
    TrilinosWrappers::MPI::Vector forces;
    /// Per cell and local row r (12 each): the row's place among this
    /// rank's rows (-1 if another rank owns it) and the places of the
    /// columns q in that row's values.
    std::vector<int> cell_row;
    std::vector<int> cell_entry;
    /// By this rank's rows: the serial DoF, whether it is a join DoF, and
    /// the diagonal's column (local numbers); by the matrix's columns:
    /// whether they are join DoFs.
    std::vector<types::global_dof_index> row_serial_dof;
    std::vector<char>                    row_is_join;
    std::vector<int>                     diagonal_column;
    std::vector<char>                    column_is_join;
    /// The values of each of this rank's rows in the Trilinos matrix (its
    /// storage does not move once the pattern is set).
    std::vector<double *>                              row_values;
    bool                                               with_tangent = false;
    std::unique_ptr<TrilinosWrappers::PreconditionAMG> amg;
    unsigned int                                       amg_builds = 0;
  };
} // namespace softface

#endif

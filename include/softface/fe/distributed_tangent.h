#ifndef softface_fe_distributed_tangent_h
#define softface_fe_distributed_tangent_h

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <softface/fe/elasticity.h>
#include <softface/fe/linear_solver.h>
#include <softface/fe/owned_rows_matrix.h>

#include <memory>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The Newton tangent and nodal forces of a nonlinear FEM model on several
   * MPI ranks, for any element on a layout's fully distributed
   * triangulation (the P1 nonlinear FEM model's, the quadratic reference's).
   * The model evaluates the cells at this rank's DoFs (add_cell()); the
   * tangent stays a Trilinos matrix on the ranks, the forces come back as
   * the model's serial vector on every rank.
   *
   * LoadSteppedNewton keeps its vectors whole on every rank, in the model's
   * serial layout: they are a small part of a run's memory (the matrix and
   * its ML are most of it), and every rank computing the same norms from the
   * same numbers makes the same decision (line search, load step, cut-back)
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
    /**
     * The DoFs of @p dof_handler, on a layout's fully distributed
     * triangulation: its k-th locally relevant DoF is the model's serial DoF
     * @p serial_dof_of_relevant[k]. @p serial_is_join are the model's join
     * DoFs; @p serial_points and @p serial_component its DoFs' support
     * points and components (ML's rigid-body modes, rotations about the
     * centroid of all the points). Where @p points_centroid is given, the
     * points need be set at this rank's own DoFs only.
     */
    DistributedTangent(
      const DoFHandler<3>                        &dof_handler,
      const std::vector<types::global_dof_index> &serial_dof_of_relevant,
      const std::vector<bool>                    &serial_is_join,
      const std::vector<Point<3>>                &serial_points,
      const std::vector<unsigned int>            &serial_component,
      const LinearSolver::Parameters             &parameters,
      const Point<3>                             *points_centroid = nullptr);

    /**
     * The cells this rank evaluates, by their DoFs (@p dofs_per_cell each,
     * in the element's order, one after the other): its own cells and the
     * ghost cells at the DoFs it owns (OwnedRowsMatrix: each cell adds to
     * the rows this rank owns only). The sparsity of this rank's rows is
     * made here, once. Collective.
     */
    void
    set_cells(const std::vector<types::global_dof_index> &cell_dofs,
              const unsigned int                          dofs_per_cell);

    /// Zero the forces and, if @p with_tangent, the tangent.
    void
    begin_assembly(const bool with_tangent);

    /// Add the forces and, if the assembly has one, the tangent of cell
    /// @p cell (its place in set_cells()) on this rank's rows.
    void
    add_cell(const unsigned int        cell,
             const Vector<double>     &cell_forces,
             const FullMatrix<double> &cell_tangent);
    /// The same for a P1 cell's closed-form response.
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
    /// The serial vector of this rank's entries @p owned_values (by its
    /// rows), on every rank. Collective.
    Vector<double>
    gather(const TrilinosWrappers::MPI::Vector &owned_values) const;

    const MPI_Comm                 communicator;
    const IndexSet                 locally_owned_dofs;
    const unsigned int             n_serial_dofs;
    const LinearSolver::Parameters parameters;
    /// The tangent (this rank's rows).
    std::unique_ptr<OwnedRowsMatrix> tangent;
    /// The tangent ML was built on (ML refers to it).
    TrilinosWrappers::SparseMatrix amg_matrix;
    /// The owned entries.
    TrilinosWrappers::MPI::Vector                      forces;
    bool                                               with_tangent = false;
    std::unique_ptr<TrilinosWrappers::PreconditionAMG> amg;
    unsigned int                                       amg_builds = 0;
    /// ML's null space: this rank's DoFs' points and components, the
    /// centroid of all the model's DoF points.
    std::vector<Point<3>>     owned_points;
    std::vector<unsigned int> owned_component;
    Point<3>                  centroid;
    /// By this rank's rows: the serial DoF and whether it is a join DoF.
    std::vector<types::global_dof_index> row_serial_dof;
    std::vector<char>                    row_is_join;
    unsigned int                         dofs_per_cell = 0;
  };
} // namespace softface

#endif

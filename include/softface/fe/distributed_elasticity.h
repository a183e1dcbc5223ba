#ifndef softface_fe_distributed_elasticity_h
#define softface_fe_distributed_elasticity_h

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <softface/core/distributed_layout.h>
#include <softface/fe/linear_solver.h>
#include <softface/fe/owned_rows_matrix.h>

#include <memory>

namespace softface
{
  using namespace dealii;

  /**
   * Linear elasticity on several MPI ranks: the
   * linear FEM model's equations (Mollemans et al. 2007, eq. 8, each cell with
   * its tissue's law, the scene's body force) on a DistributedLayout, assembled
   * on each rank's rows from the cells at them (OwnedRowsMatrix), the join DoFs
   * eliminated as on one rank, and solved by CG with ML given the six
   * rigid-body modes (LinearSolver::amg_parameters(), the serial model's
   * ML). Vertex constraints (sliding contact, lips) are not available on
   * several ranks.
   */
  namespace DistributedElasticity
  {
    struct Result
    {
      /// The displacement in the scene's serial layout, on every rank.
      Vector<double> displacement;
      bool           converged         = false;
      unsigned int   iterations        = 0;
      double         relative_residual = 0.;
    };

    /**
     * The system on a layout: assembled and preconditioned once (assemble(),
     * build_preconditioner()), then solved for any planning (solve()), as
     * the serial linear FEM model reuses its setup for every plan.
     */
    class LinearSystem
    {
    public:
      /**
       * The stiffness on this rank's cells with the join DoFs' rows and
       * columns eliminated (a Trilinos matrix). Collective; throws the same
       * error on every rank when the scene has an effect this solve does not
       * honour or @p parameters name a solver other than 'cg amg'.
       */
      void
      assemble(const DistributedLayout        &layout,
               const LinearSolver::Parameters &parameters);

      /// ML with the six rigid-body modes, as the serial model builds it.
      void
      build_preconditioner();

      /**
       * Solve with the join DoFs moved by @p prescribed (serial layout, as
       * Planning::prescribed_displacement() gives it) to the parameters'
       * relative tolerance, of the same right-hand side norm as the serial
       * model's. Collective; throws the same error on every rank when CG
       * does not converge.
       */
      Result
      solve(const Vector<double> &prescribed) const;

    private:
      const DistributedLayout         *layout = nullptr;
      LinearSolver::Parameters         parameters;
      AffineConstraints<double>        join_rows;
      std::unique_ptr<OwnedRowsMatrix> stiffness;
      /// By this rank's rows: the join rows' diagonal (as eliminated).
      std::vector<double>                                join_diagonal;
      std::unique_ptr<TrilinosWrappers::PreconditionAMG> amg;
    };

    /**
     * CG from @p solution down to the residual norm @p tolerance in at most
     * @p limit iterations, stopped where it meets negative curvature as the
     * serial LinearSolver is (@p result's flag). Adds its iterations to
     * @p result and leaves its last residual norm (not relative) in
     * @p result.relative_residual; returns whether it converged. Collective;
     * every rank takes the same decisions (they follow global norms).
     */
    bool
    cg(const TrilinosWrappers::SparseMatrix    &matrix,
       const TrilinosWrappers::PreconditionAMG &amg,
       const TrilinosWrappers::MPI::Vector     &rhs,
       TrilinosWrappers::MPI::Vector           &solution,
       const double                             tolerance,
       const unsigned int                       limit,
       LinearSolver::Result                    &result);

    /// assemble(), build_preconditioner() and solve() at once.
    Result
    solve_linear(const DistributedLayout        &layout,
                 const Vector<double>           &prescribed,
                 const LinearSolver::Parameters &parameters);
  } // namespace DistributedElasticity
} // namespace softface

#endif

#ifndef softface_models_linear_fem_h
#define softface_models_linear_fem_h

#include <deal.II/lac/precondition.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <softface/models/interface.h>
#include <softface/fe/sparse_cholesky.h>

#include <memory>

namespace softface
{
  namespace Models
  {
    /**
     * Linear FEM (seed 2.1): linearised strain, Hooke's law, K u = 0 on the
     * free DoFs with the join DoFs prescribed.
     *
     * setup() assembles K once and eliminates the join DoFs symmetrically
     * (rows and columns zeroed, diagonal kept), which does not depend on the
     * planning; it also builds the chosen solver's preconditioner or
     * factorisation. solve() only forms the right-hand side -K_fj u_j for
     * the planning and solves, so a re-plan on the same scene reuses all of
     * it. Solvers:
     *  - "gmres jacobi": the seed's choice, kept to reproduce it;
     *  - "cg amg": CG with Trilinos ML smoothed aggregation, given the six
     *    rigid-body modes as near-null space;
     *  - "direct": sparse Cholesky (CHOLMOD), factorised in setup(), two
     *    triangular solves in solve().
     */
    class LinearFEM : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;

      void
      setup(const Scene &scene) override;
      void
      solve(const Vector<double> &prescribed,
            Vector<double>       &displacement) override;

      /// Set the solver in code ("gmres jacobi", "cg amg" or "direct").
      void
      set_solver(const std::string &name, const double relative_tolerance);

      /**
       * Nodal forces (N) added to every later solve's right-hand side on the
       * free DoFs, e.g. a body load integrated against the shape functions.
       */
      void
      set_nodal_forces(const Vector<double> &forces);

      /// The stiffness matrix before the join DoFs were eliminated.
      const SparseMatrix<double> &
      stiffness_matrix() const;

      /// Number of factorisations computed so far (direct solver).
      unsigned int
      n_factorizations() const;

    private:
      void
      setup_amg();

      const Scene *scene = nullptr;

      std::string  solver_name           = "cg amg";
      double       relative_tolerance    = 1e-10;
      unsigned int max_iterations        = 10000;
      unsigned int gmres_restart         = 50;
      double       aggregation_threshold = 0.02;
      unsigned int smoother_sweeps       = 2;

      Vector<double>       nodal_forces;
      SparsityPattern      sparsity;
      SparseMatrix<double> stiffness;
      SparseMatrix<double> constrained_stiffness;

      PreconditionJacobi<SparseMatrix<double>> jacobi;
      TrilinosWrappers::SparseMatrix           trilinos_matrix;
      TrilinosWrappers::PreconditionAMG        amg;
      SparseCholesky                           direct;
      unsigned int                             factorizations = 0;
    };
  } // namespace Models
} // namespace softface

#endif

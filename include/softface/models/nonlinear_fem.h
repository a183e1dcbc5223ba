#ifndef softface_models_nonlinear_fem_h
#define softface_models_nonlinear_fem_h

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <softface/fe/hyperelasticity.h>
#include <softface/models/interface.h>
#include <softface/fe/sparse_cholesky.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace softface
{
  namespace Models
  {
    /**
     * Nonlinear FEM (seed 2.1, large deformation): full Green-Lagrange
     * strain on P1 tetrahedra with St. Venant-Kirchhoff or compressible
     * Neo-Hooke tissue, on the shared DoF layout.
     *
     * The join points' motion is applied in load steps. Each step is solved
     * by Newton's method with the consistent tangent: the first iteration
     * moves the join points to the step's target and predicts the free
     * points linearly, later ones correct with the join points fixed. Every
     * update is line-searched on the residual norm and refused if any
     * tetrahedron would invert (det F <= 0). A step that fails (inverted
     * element, no descent, no convergence, a tangent that is not positive
     * definite for the direct solver) is retried with half the increment; a
     * step that converges quickly lets the next one grow.
     *
     * Linear solves: "direct" (CHOLMOD, its ordering reused across Newton
     * iterations), "cg amg" or "gmres amg" (preconditioned by ML built once
     * on the linear stiffness, with the rigid-body modes). CG stops on
     * negative curvature: the tangent is then not positive definite, and
     * the step fails as it does when the Cholesky factorisation fails.
     *
     * With "Polynomial degree = 2" the same equations are solved with
     * quadratic tetrahedra (FE_SimplexP<3>(2), forces and tangent by
     * quadrature) on a layout of the model's own: the converged reference of
     * the accuracy benchmark. A DoF is a join DoF if it lies on a bone
     * segment's cell or boundary face; it follows the segment's rigid
     * motion, which is affine, so its value is the interpolation of the
     * join points' prescribed displacement. solve() returns the vertex
     * values; displacement_field() gives the whole quadratic field.
     *
     * "Material law = linear" solves linear FEM's small-strain equations
     * with the same machinery (one Newton iteration with a direct solver):
     * with quadratic tetrahedra it measures linear elasticity's model error
     * apart from P1's discretisation error.
     */
    class NonlinearFEM : public Interface
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

      /// Set the main options in code (tests, benchmarks).
      void
      set_options(const std::string &law,
                  const std::string &solver,
                  const double       initial_increment = 1.,
                  const unsigned int polynomial_degree = 1);

      /// The quadratic field after solve() with degree 2, else nothing.
      std::pair<const DoFHandler<3> *, const Vector<double> *>
      displacement_field() const override;

      /// The DoFs the model solves for (3 per vertex for degree 1).
      unsigned int
      n_dofs() const;

      /**
       * Internal nodal forces at @p u (all DoFs) and, if @p tangent is not
       * null, the unconstrained tangent (on sparsity_pattern()). Returns
       * false if a tetrahedron is inverted.
       */
      bool
      evaluate(const Vector<double> &u,
               Vector<double>       &forces,
               SparseMatrix<double> *tangent) const;

      const SparsityPattern &
      sparsity_pattern() const;

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
      const Report &
      report() const;

    private:
      /// Outcome of one load step's Newton solve.
      struct StepResult
      {
        bool         converged  = false;
        unsigned int iterations = 0;
        double       residual   = 0.;
        std::string  reason;
      };
      StepResult
      newton(Vector<double> &u, const Vector<double> &target);
      bool
      linear_solve(const Vector<double> &rhs,
                   Vector<double>       &solution,
                   std::string          &reason);
      double
      free_norm(const Vector<double> &v) const;
      void
      setup_quadratic(Timer &timer);
      /// ML on amg_matrix, with the rigid-body modes of the layout.
      void
      build_amg();

      Hyperelasticity::Law law               = Hyperelasticity::Law::neo_hooke;
      std::string          solver_name       = "cg amg";
      double               initial_increment = 1.;
      double               minimum_increment = 1e-3;
      unsigned int         max_newton_iterations = 20;
      double               residual_tolerance    = 1e-10;
      double               linear_tolerance      = 1e-6;
      unsigned int         degree                = 1;
      unsigned int         amg_rebuild_iterations = 100;

      const Scene                                         *scene = nullptr;
      std::vector<std::array<types::global_dof_index, 12>> cell_dofs;
      std::vector<std::array<Tensor<1, 3>, 4>>             cell_gradients;
      std::vector<double>                                  cell_volumes;
      std::vector<unsigned int>                            cell_entry_positions;
      /// True for the join DoFs of the layout solved on.
      std::vector<bool> is_join;

      // Degree 2 only: the layout, each DoF's value as a combination of the
      // vertex DoFs of its cell (for the prescribed motion), the DoF at each
      // vertex DoF (for the returned vertex values), and the solution.
      std::unique_ptr<FESystem<3>>   quadratic_fe;
      std::unique_ptr<DoFHandler<3>> quadratic_dofs;
      std::vector<std::array<std::pair<types::global_dof_index, double>, 4>>
                                           from_vertex_dofs;
      std::vector<types::global_dof_index> at_vertex_dof;
      std::vector<Point<3>>                dof_points;
      std::vector<unsigned int>            dof_component;
      Vector<double>                       quadratic_solution;

      SparsityPattern                   sparsity;
      SparseMatrix<double>              tangent;
      TrilinosWrappers::SparseMatrix    amg_matrix;
      TrilinosWrappers::PreconditionAMG amg;
      SparseCholesky                    cholesky;

      double reference_force = 0.;
      Report last_report;
      double time_assembly = 0., time_linear = 0.;
    };
  } // namespace Models
} // namespace softface

#endif

#ifndef softface_models_linear_fem_h
#define softface_models_linear_fem_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <softface/fe/linear_solver.h>
#include <softface/fe/vertex_constraints.h>
#include <softface/models/interface.h>

#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

namespace softface
{
  class DistributedLayout;
  namespace DistributedElasticity
  {
    class LinearSystem;
  }

  namespace Models
  {
    /**
     * Linear FEM (Mollemans et al. 2007, Sec. 2.1): linearised strain, Hooke's
     * law, K u = 0 on the free DoFs with the join DoFs prescribed.
     *
     * setup() assembles K once and eliminates the join DoFs symmetrically
     * (rows and columns zeroed, diagonal kept), which does not depend on the
     * planning; it also builds the chosen solver's preconditioner or
     * factorisation (fe/linear_solver.h). solve() only forms the right-hand
     * side -K_fj u_j for the planning and solves, so a re-plan on the same
     * scene reuses all of it.
     *
     * On several MPI ranks the scene's cells are shared among the
     * ranks (DistributedLayout) and the system is assembled and solved there
     * (DistributedElasticity::LinearSystem, 'cg amg' only); every rank gets
     * the whole answer.
     */
    class LinearFEM : public Interface
    {
    public:
      LinearFEM();
      ~LinearFEM() override;

      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;
      /// Tissues per cell and body forces.
      unsigned int
      honoured_effects() const override;
      /// True without unilateral contact (the active set is not linear).
      bool
      linear_in_motion(const Scene &scene) const override;
      /// With 'cg amg' (the solver it has on several ranks): its ranks read
      /// their part of the mesh (DistributedLayout) only.
      bool
      runs_without_scene_cells() const override;

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


    protected:
      void
      do_setup(const Scene &scene) override;
      void
      do_solve(const Vector<double> &prescribed,
               Vector<double>       &displacement) override;

    private:
      const Scene *scene = nullptr;

      LinearSolver::Parameters solver_parameters;
      LinearSolver             linear_solver;
      unsigned int             factorizations = 0;

      Vector<double>       nodal_forces;
      SparsityPattern      sparsity;
      SparseMatrix<double> stiffness;
      SparseMatrix<double> constrained_stiffness;
      // With vertex constraints (sliding contact, lips): their lines, the
      // stiffness condensed with the holding ones, and which lines those
      // were when it was condensed.
      std::unique_ptr<VertexConstraintSet> vertex_constraints;
      SparseMatrix<double>                 condensed_stiffness;
      std::vector<bool>                    condensed_for;

      const DistributedLayout                             *layout = nullptr;
      std::unique_ptr<DistributedElasticity::LinearSystem> distributed;

      void
      setup_distributed();
    };
  } // namespace Models
} // namespace softface

#endif

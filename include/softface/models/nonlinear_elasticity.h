#ifndef softface_models_nonlinear_elasticity_h
#define softface_models_nonlinear_elasticity_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <softface/core/distributed_layout.h>
#include <softface/fe/distributed_tangent.h>
#include <softface/fe/linear_solver.h>
#include <softface/fe/material_law.h>
#include <softface/fe/newton.h>
#include <softface/fe/vertex_constraints.h>
#include <softface/models/interface.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace softface
{
  namespace Models
  {
    /**
     * What the large-deformation models share (Mollemans et al. 2007, Sec. 2.1,
     * the full Green-Lagrange strain): the material law (fe/material_law.h),
     * the load-stepped Newton iteration (fe/newton.h), the linear solves
     * (fe/linear_solver.h, ML built on the stiffness at rest), and their
     * parameters. A derived model provides the discretisation: its layout,
     * which DoFs are join DoFs and how they follow the planning, and the
     * forces and tangent at a displacement.
     */
    class NonlinearElasticity : public Interface
    {
    public:
      /// The entries both nonlinear models declare in their subsection.
      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;

      /// Set the main options in code (tests, benchmarks).
      void
      set_options(const std::string &law,
                  const std::string &solver,
                  const double       initial_increment = 1.);
      /// Rebuild ML on the tangent after this many iterations of a solve.
      void
      set_amg_rebuild_iterations(const unsigned int iterations);

      /**
       * Internal nodal forces at @p u (all DoFs of the model's layout) and,
       * if @p tangent is not null, the unconstrained tangent (on
       * sparsity_pattern()). Returns false if a tetrahedron is inverted.
       */
      virtual bool
      evaluate(const Vector<double> &u,
               Vector<double>       &forces,
               SparseMatrix<double> *tangent) const = 0;

      const SparsityPattern &
      sparsity_pattern() const;

      /// Where evaluate() last refused a state (" (cell N at (x, y, z))"),
      /// or empty.
      const std::string &
      last_refusal() const;

      /// The DoFs the model solves for.
      unsigned int
      n_dofs() const;

      /// Where it evaluates on the ranks (why_not_on_ranks_by_parameters()
      /// empty): each rank reads its part of the mesh only.
      bool
      runs_without_scene_cells() const override;

      const LoadSteppedNewton::Report &
      report() const;

    protected:
      explicit NonlinearElasticity(const std::string &name);

      /**
       * Build the layout: fill is_join and sparsity, and, for a layout other
       * than the scene's, dof_points and dof_component (ML's rigid-body
       * modes; on several MPI ranks do_setup() frees them once the
       * distributed tangent holds its own rows' points, and they need be
       * set at the rank's own DoFs only where dof_points_centroid is set).
       */
      virtual void
      setup_layout() = 0;
      /// The join DoFs' motion on the layout for the vertex values
      /// @p prescribed on the shared layout.
      virtual void
      join_motion(const Vector<double> &prescribed,
                  Vector<double>       &motion) const = 0;
      /// The vertex values (shared layout) of a solution @p u on the layout.
      virtual void
      vertex_values(const Vector<double> &u, Vector<double> &displacement) = 0;
      /// The initial guess @p guess (vertex values of the shared layout) in
      /// the layout's numbering, in @p translated if it must be moved
      /// there; by default @p guess itself. Collective where it moves it.
      virtual const Vector<double> *
      guess_in_model_numbering(const Vector<double> *guess,
                               Vector<double>       &translated) const;

      /**
       * On several MPI ranks: why the model runs whole on every rank, or
       * empty if a derived model that evaluates on the ranks may (Solver
       * 'cg amg', Newton's own loop, 'Indefinite tangent = cut back', no
       * stability test, no vertex constraints: what needs the whole tangent
       * stays serial).
       */
      std::string
      why_not_on_ranks() const;
      /// The part of why_not_on_ranks() its parameters decide, known before
      /// any scene (all of it but the scene's vertex constraints).
      std::string
      why_not_on_ranks_by_parameters() const;

      /**
       * The forces (serial layout, every rank) and, if @p with_tangent, the
       * tangent into distributed_tangent, from this rank's cells of
       * ranks_layout; false on every rank if a cell of any rank refuses the
       * state. Collective. Only for a model whose setup_layout() set
       * ranks_layout.
       */
      virtual bool
      evaluate_on_ranks(const Vector<double> &u,
                        Vector<double>       &forces,
                        const bool            with_tangent) const;

      /**
       * The end of evaluate_on_ranks(): the forces gathered into @p forces,
       * and the first cell of all ranks that refused the state (@p refused:
       * this rank's, invalid_unsigned_int if none; the scene's cell number)
       * described in the refusal; false if there is one. Collective.
       */
      bool
      end_evaluation_on_ranks(Vector<double> &forces,
                              unsigned int    refused) const;

      void
      do_setup(const Scene &scene) override;
      void
      do_solve(const Vector<double> &prescribed,
               Vector<double>       &displacement) override;

      const std::string model_name;
      MaterialLaw::Law  law   = MaterialLaw::Law::neo_hooke;
      const Scene      *scene = nullptr;

      std::vector<bool>         is_join;
      SparsityPattern           sparsity;
      std::vector<Point<3>>     dof_points;
      std::vector<unsigned int> dof_component;
      /// On several MPI ranks, where a model sets dof_points at the DoFs a
      /// rank owns only: the centroid of all (ML's rotations turn about it).
      std::optional<Point<3>> dof_points_centroid;
      /// Set by evaluate() when it refuses a state.
      mutable std::string refusal;
      /// " (cell N at (x, y, z), join points of 'a' 'b')": where a refused
      /// cell (active cell index of the scene's mesh) is and which
      /// segments' join points it has.
      std::string
      describe_cell(const unsigned int cell_index) const;
      /// External nodal forces on the model's layout (gravity), applied in
      /// the load steps with the join motion; none if null.
      const Vector<double> *body_force = nullptr;
      /// Constraints on free vertices of the shared layout (sliding
      /// contact, lips), if the layout is the shared one and has any.
      std::unique_ptr<VertexConstraintSet> vertex_constraints;
      /// On several MPI ranks, the run's layout if setup_layout() chose to
      /// evaluate on the ranks (why_not_on_ranks() empty); then the serial
      /// sparsity is left empty and the tangent lives in
      /// distributed_tangent, which do_setup() builds from what
      /// setup_layout() put in the ranks_* members: the model's DoFs on the
      /// layout's triangulation, the serial DoF (the index into the model's
      /// whole vectors; the DoF itself where the model numbers them on the
      /// ranks' parts, as the quadratic reference does) of each locally
      /// relevant one (in the order of the index set), and the DoFs of the
      /// cells this rank evaluates (emptied once the tangent has them).
      const DistributedLayout             *ranks_layout      = nullptr;
      const DoFHandler<3>                 *ranks_dof_handler = nullptr;
      std::vector<types::global_dof_index> ranks_serial_dofs;
      std::vector<types::global_dof_index> ranks_cell_dofs;
      unsigned int                         ranks_dofs_per_cell = 0;
      std::unique_ptr<DistributedTangent>  distributed_tangent;

    private:
      LoadSteppedNewton::Parameters newton_parameters;
      LinearSolver::Parameters      solver_parameters;
      LinearSolver                  linear_solver;
      SparseMatrix<double>          tangent;
      LoadSteppedNewton::Report     last_report;
    };
  } // namespace Models
} // namespace softface

#endif

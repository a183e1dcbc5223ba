// The linear FEM model (models; Mollemans et al. 2007, Sec. 2.1): the P1
// stiffness of the shared layout, assembled once per scene with the join DoFs
// eliminated, and one linear solve per planning (fe/linear_solver.h).

#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>
#include <softface/core/point_mesh.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/distributed_elasticity.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/point_block_pattern.h>
#include <softface/models/linear_fem.h>

#include <sstream>

namespace softface
{
  namespace Models
  {
    LinearFEM::LinearFEM() = default;

    LinearFEM::~LinearFEM() = default;

    void
    LinearFEM::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry(
        "Solver",
        "cg amg",
        Patterns::Selection("gmres jacobi|cg amg|direct"),
        "Linear solver: 'gmres jacobi' (as in Mollemans et al. 2007), 'cg amg' "
        "(CG with "
        "Trilinos ML algebraic multigrid and the six rigid-body modes), "
        "'direct' (sparse Cholesky by CHOLMOD; factorised once per scene, "
        "reused by every planning).");
      prm.declare_entry("Relative tolerance",
                        "1e-10",
                        Patterns::Double(0., 1.),
                        "Iterative solvers stop when the residual norm falls "
                        "below this fraction of the right-hand side's norm.");
      prm.declare_entry("Maximum iterations",
                        "20000",
                        Patterns::Integer(1),
                        "An iterative solve that needs more iterations stops "
                        "with an error stating the residual reached.");
      LinearSolver::Parameters().declare_tuning_parameters(prm, false);
    }

    void
    LinearFEM::parse_parameters(ParameterHandler &prm)
    {
      solver_parameters.method = prm.get("Solver");
      solver_parameters.relative_tolerance =
        prm.get_double("Relative tolerance");
      solver_parameters.max_iterations = prm.get_integer("Maximum iterations");
      solver_parameters.parse_tuning_parameters(prm, false);
    }

    unsigned int
    LinearFEM::honoured_effects() const
    {
      return SceneEffects::cell_materials | SceneEffects::body_forces |
             SceneEffects::free_vertex_constraints;
    }

    bool
    LinearFEM::linear_in_motion(const Scene &scene) const
    {
      return !has_unilateral_contact(scene);
    }

    bool
    LinearFEM::runs_without_scene_cells() const
    {
      return solver_parameters.method == "cg amg";
    }

    void
    LinearFEM::set_solver(const std::string &name, const double tolerance)
    {
      AssertThrow(name == "gmres jacobi" || name == "cg amg" ||
                    name == "direct",
                  ExcMessage("Unknown linear solver '" + name + "'."));
      solver_parameters.method             = name;
      solver_parameters.relative_tolerance = tolerance;
    }

    void
    LinearFEM::do_setup(const Scene &scene_in)
    {
      scene = &scene_in;
      distributed.reset();
      layout = nullptr;
      if (Utilities::MPI::n_mpi_processes(communicator) > 1)
        {
          setup_distributed();
          return;
        }
      // Without vertex constraints (whose fill joins a slit's sides) the
      // pattern is the points' neighbours (PointBlockPattern).
      std::unique_ptr<PointMesh>         points;
      std::unique_ptr<PointBlockPattern> pattern;
      {
        const auto timed = phase("sparsity");
        if (!scene->has_vertex_constraints() && scene->dofs_are_point_blocks())
          {
            points  = std::make_unique<PointMesh>(*scene, "linear fem");
            pattern = std::make_unique<PointBlockPattern>(*points);
            pattern->make_sparsity(sparsity);
          }
        else
          ConstrainedSystem::make_sparsity_pattern(*scene, sparsity);
      }
      {
        const auto timed = phase("assemble");
        Elasticity::assemble_p1_stiffness(*scene,
                                          sparsity,
                                          stiffness,
                                          pattern.get());
      }
      pattern.reset();
      points.reset();
      // The coupling K_fj that the elimination removes stays available in
      // 'stiffness' for the right-hand side of every planning.
      {
        const auto timed = phase("eliminate join DoFs");
        constrained_stiffness.reinit(sparsity);
        constrained_stiffness.copy_from(stiffness);
        ConstrainedSystem::eliminate_join_dofs(scene->join_dofs(),
                                               constrained_stiffness);
      }
      const auto timed = phase(
        solver_parameters.method == "direct" ? "factorise" : "preconditioner");
      linear_solver.initialize(solver_parameters, *scene);
      vertex_constraints.reset();
      if (scene->has_vertex_constraints())
        {
          vertex_constraints = std::make_unique<VertexConstraintSet>(*scene);
          condensed_for.clear();
          vertex_constraints->condense_for_holding(constrained_stiffness,
                                                   condensed_stiffness,
                                                   condensed_for,
                                                   linear_solver,
                                                   "linear fem");
        }
      else if (!linear_solver.set_matrix(constrained_stiffness))
        throw Error("linear fem (direct): the Cholesky factorisation failed; "
                    "the stiffness is not positive definite.");
      factorizations += linear_solver.n_factorizations();
    }

    void
    LinearFEM::setup_distributed()
    {
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(communicator);
      if (solver_parameters.method != "cg amg")
        throw Error("linear fem: on " + std::to_string(n_ranks) +
                    " MPI ranks the solver is 'cg amg' only (a '" +
                    solver_parameters.method +
                    "' solve is not distributed); set Models/linear fem/Solver "
                    "= cg amg or run on one rank.");
      if (scene->has_vertex_constraints())
        throw Error("linear fem: sliding contact and separated lips are not "
                    "available on several MPI ranks; run this scene on one "
                    "rank.");
      if (nodal_forces.size() > 0)
        throw Error("linear fem: nodal forces are not available on several "
                    "MPI ranks.");
      {
        const auto timed = phase("partition");
        layout           = &distributed_layout(*scene);
      }
      distributed = std::make_unique<DistributedElasticity::LinearSystem>();
      {
        const auto timed = phase("assemble");
        distributed->assemble(*layout, solver_parameters);
      }
      const auto timed = phase("preconditioner");
      distributed->build_preconditioner();
      add_detail("MPI ranks", n_ranks);
    }

    void
    LinearFEM::do_solve(const Vector<double> &prescribed,
                        Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("LinearFEM::setup() first."));
      if (distributed)
        {
          if (nodal_forces.size() > 0)
            throw Error("linear fem: nodal forces are not available on several "
                        "MPI ranks.");
          const auto timed  = phase("solve");
          auto       result = distributed->solve(prescribed);
          displacement.swap(result.displacement);
          set_iterations(result.iterations);
          set_residual(result.relative_residual);
          return;
        }
      const std::vector<bool> &is_join = scene->join_dofs();
      const unsigned int       n       = is_join.size();

      // -K_fj u_j (+ f) on the free rows, K_jj u_j on the join rows.
      // External forces: those set by set_nodal_forces() and the scene's
      // body force (gravity), if any.
      Vector<double> rhs, minus_forces;
      const bool loaded = nodal_forces.size() == n || scene->has_body_force();
      if (loaded)
        {
          minus_forces.reinit(n);
          if (nodal_forces.size() == n)
            minus_forces -= nodal_forces;
          if (scene->has_body_force())
            minus_forces -= scene->effects.body_force;
        }
      ConstrainedSystem::right_hand_side(
        stiffness, is_join, prescribed, loaded ? &minus_forces : nullptr, rhs);

      // Start from the join values, so that the join rows hold at once.
      displacement.reinit(n);
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          displacement[i] = prescribed[i];
      LinearSolver::Result result;
      if (vertex_constraints)
        {
          const auto timed  = phase("solve");
          const auto report = vertex_constraints->solve_with_active_set(
            stiffness,
            constrained_stiffness,
            condensed_stiffness,
            condensed_for,
            linear_solver,
            rhs,
            prescribed,
            loaded ? &minus_forces : nullptr,
            scene->effects.active_set_limit(),
            "linear fem",
            displacement);
          result = report.result;
          add_detail("contact active-set iterations", report.rounds);
          add_detail("contact constraints holding",
                     vertex_constraints->n_holding());
        }
      else
        {
          const auto timed = phase("solve");
          result           = linear_solver.solve(rhs, displacement);
        }
      if (!result.converged)
        {
          std::ostringstream m;
          m << "linear fem (" << solver_parameters.method
            << "): no convergence in " << result.iterations
            << " iterations; relative residual reached "
            << result.relative_residual << " (tolerance "
            << solver_parameters.relative_tolerance
            << "). Raise 'Maximum iterations' or pick another solver.";
          throw Error(m.str());
        }
      set_iterations(result.iterations);

      // Put the join values back exactly (an iterative solve leaves them
      // correct only to its tolerance).
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          displacement[i] = prescribed[i];

      Vector<double> residual(n);
      constrained_stiffness.vmult(residual, displacement);
      residual -= rhs;
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          residual[i] = 0.;
      // What the constraints take up is not a residual.
      if (vertex_constraints)
        vertex_constraints->condense(residual);
      set_residual(residual.l2_norm() / std::max(rhs.l2_norm(), 1e-300));
    }

    void
    LinearFEM::set_nodal_forces(const Vector<double> &forces)
    {
      nodal_forces = forces;
    }

    const SparseMatrix<double> &
    LinearFEM::stiffness_matrix() const
    {
      Assert(!distributed,
             ExcMessage("A distributed linear fem holds no serial matrix."));
      return stiffness;
    }

    unsigned int
    LinearFEM::n_factorizations() const
    {
      return factorizations;
    }

    SOFTFACE_REGISTER_MODEL(
      LinearFEM,
      "linear fem",
      "Linear elasticity on P1 tetrahedra (Mollemans et al. 2007, Sec. 2.1), "
      "solved by GMRES/Jacobi, CG/AMG or a reused "
      "direct factorisation.")
  } // namespace Models
} // namespace softface

#include <deal.II/base/timer.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <softface/fe/elasticity_amg.h>
#include <softface/core/error.h>
#include <softface/fe/linear_elasticity.h>
#include <softface/models/linear_fem.h>


namespace softface
{
  namespace Models
  {
    void
    LinearFEM::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry(
        "Solver",
        "cg amg",
        Patterns::Selection("gmres jacobi|cg amg|direct"),
        "Linear solver: 'gmres jacobi' (the seed's), 'cg amg' (CG with "
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
      prm.declare_entry("GMRES restart",
                        "50",
                        Patterns::Integer(1),
                        "Krylov vectors kept before GMRES restarts.");
      prm.declare_entry("AMG smoother sweeps",
                        "2",
                        Patterns::Integer(1, 10),
                        "Chebyshev smoother sweeps before and after each "
                        "coarse correction of the AMG V-cycle.");
      prm.declare_entry("AMG aggregation threshold",
                        "0.02",
                        Patterns::Double(0., 1.),
                        "ML's aggregation threshold: matrix entries smaller "
                        "than this (relative) are dropped when aggregating.");
    }

    void
    LinearFEM::parse_parameters(ParameterHandler &prm)
    {
      solver_name           = prm.get("Solver");
      relative_tolerance    = prm.get_double("Relative tolerance");
      max_iterations        = prm.get_integer("Maximum iterations");
      gmres_restart         = prm.get_integer("GMRES restart");
      aggregation_threshold = prm.get_double("AMG aggregation threshold");
      smoother_sweeps       = prm.get_integer("AMG smoother sweeps");
    }

    void
    LinearFEM::set_solver(const std::string &name, const double tolerance)
    {
      AssertThrow(name == "gmres jacobi" || name == "cg amg" ||
                    name == "direct",
                  ExcMessage("Unknown linear solver '" + name + "'."));
      solver_name        = name;
      relative_tolerance = tolerance;
    }

    void
    LinearFEM::setup(const Scene &scene_in)
    {
      scene = &scene_in;
      stats = Statistics();
      Timer total, phase;

      LinearElasticity::make_sparsity_pattern(*scene, sparsity);
      stats.phases.emplace_back("sparsity", phase.wall_time());
      phase.restart();
      stiffness.reinit(sparsity);
      LinearElasticity::assemble_stiffness(*scene, stiffness);
      stats.phases.emplace_back("assemble", phase.wall_time());

      // Eliminate the join DoFs symmetrically: their rows and columns are
      // zeroed and the diagonal kept, so the matrix stays SPD and does not
      // depend on where the join points move to. The coupling K_fj that the
      // elimination removes stays available in 'stiffness' for the
      // right-hand side.
      phase.restart();
      constrained_stiffness.reinit(sparsity);
      constrained_stiffness.copy_from(stiffness);
      LinearElasticity::eliminate_join_dofs(scene->join_dofs(),
                                            constrained_stiffness);
      stats.phases.emplace_back("eliminate join DoFs", phase.wall_time());

      phase.restart();
      if (solver_name == "gmres jacobi")
        jacobi.initialize(constrained_stiffness);
      else if (solver_name == "cg amg")
        setup_amg();
      else
        {
          direct.factorize(constrained_stiffness);
          ++factorizations;
        }
      stats.phases.emplace_back(solver_name == "direct" ? "factorise" :
                                                          "preconditioner",
                                phase.wall_time());
      stats.setup_time = total.wall_time();
    }

    void
    LinearFEM::setup_amg()
    {
      trilinos_matrix.reinit(constrained_stiffness);
      initialize_elasticity_amg(
        *scene, trilinos_matrix, aggregation_threshold, smoother_sweeps, amg);
    }

    void
    LinearFEM::solve(const Vector<double> &prescribed,
                     Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("LinearFEM::setup() first."));
      Timer                    timer;
      const std::vector<bool> &is_join = scene->join_dofs();
      const unsigned int       n       = is_join.size();

      // The join values alone, then the right-hand side -K_fj u_j on the
      // free rows and K_jj u_j on the (diagonal) join rows.
      Vector<double> join_values(n);
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          join_values[i] = prescribed[i];
      Vector<double> rhs(n);
      stiffness.vmult(rhs, join_values);
      rhs *= -1.;
      if (nodal_forces.size() == n)
        rhs += nodal_forces;
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          rhs[i] = constrained_stiffness.diag_element(i) * join_values[i];

      displacement     = join_values;
      stats.iterations = 1;
      if (solver_name == "direct")
        direct.solve(rhs, displacement);
      else
        {
          SolverControl control(max_iterations,
                                relative_tolerance * rhs.l2_norm(),
                                false,
                                false);
          try
            {
              if (solver_name == "cg amg")
                {
                  SolverCG<Vector<double>> cg(control);
                  cg.solve(constrained_stiffness, displacement, rhs, amg);
                }
              else
                {
                  SolverGMRES<Vector<double>> gmres(
                    control,
                    SolverGMRES<Vector<double>>::AdditionalData(gmres_restart +
                                                                2));
                  gmres.solve(constrained_stiffness, displacement, rhs, jacobi);
                }
            }
          catch (const SolverControl::NoConvergence &e)
            {
              throw Error("linear fem (" + solver_name +
                          "): no convergence "
                          "in " +
                          std::to_string(e.last_step) +
                          " iterations; relative residual reached " +
                          std::to_string(e.last_residual / rhs.l2_norm()) +
                          " (tolerance " + std::to_string(relative_tolerance) +
                          "). Raise 'Maximum iterations' or pick another "
                          "solver.");
            }
          stats.iterations = control.last_step();
        }

      // Put the join values back exactly (an iterative solve leaves them
      // correct only to its tolerance).
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          displacement[i] = join_values[i];

      Vector<double> residual(n);
      constrained_stiffness.vmult(residual, displacement);
      residual -= rhs;
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          residual[i] = 0.;
      stats.residual   = residual.l2_norm() / std::max(rhs.l2_norm(), 1e-300);
      stats.solve_time = timer.wall_time();
    }

    void
    LinearFEM::set_nodal_forces(const Vector<double> &forces)
    {
      nodal_forces = forces;
    }

    const SparseMatrix<double> &
    LinearFEM::stiffness_matrix() const
    {
      return stiffness;
    }

    unsigned int
    LinearFEM::n_factorizations() const
    {
      return factorizations;
    }

    SOFTFACE_REGISTER_MODEL(LinearFEM,
                            "linear fem",
                            "Linear elasticity on P1 tetrahedra (seed 2.1), "
                            "solved by GMRES/Jacobi, CG/AMG or a reused "
                            "direct factorisation.")
  } // namespace Models
} // namespace softface

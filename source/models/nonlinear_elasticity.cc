// What the nonlinear FEM models share (models): their parameters, the setup
// of the linear solver on the stiffness at rest, and the load-stepped Newton
// solve of a planning; the discretisations live in nonlinear_fem.cc (P1) and
// reference_fem.cc (quadrature, quadratic tetrahedra).

#include <softface/core/error.h>
#include <softface/core/release.h>
#include <softface/fe/constrained_system.h>
#include <softface/models/nonlinear_elasticity.h>

#include <iterator>
#include <set>
#include <sstream>

namespace softface
{
  namespace Models
  {
    NonlinearElasticity::NonlinearElasticity(const std::string &name)
        : model_name(name)
    {
      solver_parameters.method                 = "cg amg";
      solver_parameters.relative_tolerance     = 1e-6;
      solver_parameters.max_iterations         = 2000;
      solver_parameters.amg_rebuild_iterations = 100;
      // Newton reuses one ML over many solves: fewer iterations pay more
      // than a cheaper setup (unsmoothed aggregates made the 511k cube's
      // Newton solve 1.6 times slower, 210 -> 352 CG iterations).
      solver_parameters.amg_smoothed_aggregation = true;
    }

    void
    NonlinearElasticity::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Material law",
                        "neo-hooke",
                        Patterns::Selection(MaterialLaw::selection()),
                        "'st venant-kirchhoff' (the law of Mollemans et al. "
                        "2007, and CalculiX's "
                        "*ELASTIC with NLGEOM; softens under strong "
                        "compression), compressible 'neo-hooke' (stiffens "
                        "under compression), or 'linear': linear FEM's "
                        "small-strain equations solved with this model's "
                        "machinery. Lame parameters from Young's modulus and "
                        "Poisson's ratio as for the linear models.");
      prm.declare_entry("Solver",
                        "cg amg",
                        Patterns::Selection("direct|cg amg|gmres amg"),
                        "Linear solver of each Newton iteration: 'direct' "
                        "(CHOLMOD, ordering reused), 'cg amg' or 'gmres amg' "
                        "(Trilinos ML on the stiffness at rest; rebuilt on the "
                        "tangent when a solve gets slow). CG stops when it "
                        "meets negative curvature (the tangent is not "
                        "positive definite) and the load step is cut back, "
                        "as when the direct solver's factorisation fails.");
      LoadSteppedNewton::Parameters::declare_parameters(prm);
      prm.declare_entry("Linear tolerance",
                        "1e-6",
                        Patterns::Double(0., 1.),
                        "Relative residual of the iterative linear solves "
                        "inside Newton.");
      prm.declare_entry("Maximum linear iterations",
                        "2000",
                        Patterns::Integer(1),
                        "An iterative linear solve inside Newton that needs "
                        "more iterations fails, and the load step is cut "
                        "back.");
      LinearSolver::Parameters defaults;
      defaults.amg_rebuild_iterations   = 100;
      defaults.amg_smoothed_aggregation = true;
      defaults.declare_tuning_parameters(prm, true);
    }

    void
    NonlinearElasticity::parse_parameters(ParameterHandler &prm)
    {
      law = MaterialLaw::from_name(prm.get("Material law"));
      solver_parameters.method = prm.get("Solver");
      newton_parameters.parse_parameters(prm, model_name);
      solver_parameters.relative_tolerance = prm.get_double("Linear tolerance");
      solver_parameters.max_iterations =
        prm.get_integer("Maximum linear iterations");
      solver_parameters.parse_tuning_parameters(prm, true);
    }

    void
    NonlinearElasticity::set_options(const std::string &law_name,
                                     const std::string &solver,
                                     const double       increment)
    {
      law                                 = MaterialLaw::from_name(law_name);
      solver_parameters.method            = solver;
      newton_parameters.initial_increment = increment;
    }

    void
    NonlinearElasticity::set_amg_rebuild_iterations(
      const unsigned int iterations)
    {
      solver_parameters.amg_rebuild_iterations = iterations;
    }

    void
    NonlinearElasticity::do_setup(const Scene &scene_in)
    {
      scene             = &scene_in;
      body_force        = nullptr;
      ranks_layout      = nullptr;
      ranks_dof_handler = nullptr;
      distributed_tangent.reset();
      dof_points.clear();
      dof_component.clear();
      dof_points_centroid.reset();
      setup_layout();
      set_n_dofs(is_join.size());
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(communicator);
      if (ranks_layout != nullptr)
        {
          // Nothing serial is kept from an earlier setup.
          tangent.clear();
          sparsity.reinit(0, 0, 0);
          linear_solver.initialize(solver_parameters, {}, {});
          {
            const auto timed = phase("matrix positions");
            // The shared layout's points if the model has none of its own.
            std::vector<Point<3>>     scene_points;
            std::vector<unsigned int> scene_component;
            if (dof_points.empty())
              LinearSolver::scene_dof_points(*scene,
                                             scene_points,
                                             scene_component);
            distributed_tangent = std::make_unique<DistributedTangent>(
              *ranks_dof_handler,
              ranks_serial_dofs,
              is_join,
              dof_points.empty() ? scene_points : dof_points,
              dof_points.empty() ? scene_component : dof_component,
              solver_parameters,
              dof_points_centroid ? &*dof_points_centroid : nullptr);
            distributed_tangent->set_cells(ranks_cell_dofs,
                                           ranks_dofs_per_cell);
            release(ranks_cell_dofs);
            release(ranks_serial_dofs);
            // The tangent keeps its own rows' points for ML; the layout's
            // whole (28 bytes per DoF on every rank) are not read again.
            release(dof_points);
            release(dof_component);
          }
          // ML on the tangent at rest, as on one rank.
          const auto     timed = phase("preconditioner");
          Vector<double> zero(is_join.size()), forces, rhs;
          evaluate_on_ranks(zero, forces, true);
          distributed_tangent->right_hand_side_and_eliminate(zero, forces, rhs);
          distributed_tangent->build_amg();
          add_detail("MPI ranks", n_ranks);
          return;
        }
      if (n_ranks > 1)
        {
          const std::string why = why_not_on_ranks();
          add_detail("MPI ranks",
                     "1 (" +
                       (why.empty() ? "not distributed: whole on every rank" :
                                      why) +
                       ")");
        }
      tangent.reinit(sparsity);

      const auto timed = phase("preconditioner");
      if (dof_points.empty())
        linear_solver.initialize(solver_parameters, *scene);
      else
        linear_solver.initialize(solver_parameters, dof_points, dof_component);
      if (solver_parameters.method != "direct")
        {
          // ML is built once, on the tangent at rest (every law's is the
          // linear stiffness): close enough to the later tangents, and
          // rebuilt when a solve says otherwise.
          Vector<double> zero(is_join.size()), forces;
          evaluate(zero, forces, &tangent);
          ConstrainedSystem::eliminate_join_dofs(is_join, tangent);
          // With constraints, on the tangent they condense: a slit's sides
          // are tied only through them, and ML built without them was not
          // a positive definite preconditioner (CG met negative curvature).
          if (vertex_constraints)
            vertex_constraints->condense(tangent);
          linear_solver.build_amg(tangent);
        }
    }

    void
    NonlinearElasticity::do_solve(const Vector<double> &prescribed,
                                  Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("setup() first."));
      last_report = LoadSteppedNewton::Report();
      refusal.clear();
      Vector<double> motion(is_join.size()), u;
      join_motion(prescribed, motion);

      const std::string description = model_name + " (" +
                                      MaterialLaw::name(law) + ", " +
                                      solver_parameters.method + ")";
      const std::string hint =
        law == MaterialLaw::Law::st_venant_kirchhoff ?
          " St. Venant-Kirchhoff softens under strong compression and may "
          "have no equilibrium here; 'Material law = neo-hooke' does." :
          "";
      LoadSteppedNewton::Parameters newton_prm = newton_parameters;
      newton_prm.check_stability = law == MaterialLaw::Law::st_venant_kirchhoff;
      LoadSteppedNewton newton(
        newton_prm,
        [this](const Vector<double> &v,
               Vector<double>       &forces,
               SparseMatrix<double> *matrix) {
          return distributed_tangent ?
                   evaluate_on_ranks(v, forces, matrix != nullptr) :
                   evaluate(v, forces, matrix);
        },
        tangent,
        is_join,
        linear_solver,
        [this]() { return refusal; });
      if (load_path)
        newton.set_path([this](const double    load,
                               Vector<double> &target,
                               Vector<double> &bone) {
          bone = load_path(load);
          join_motion(bone, target);
        });
      Vector<double> guess;
      newton.set_initial_guess(guess_in_model_numbering(initial_guess, guess));
      newton.set_distributed_tangent(distributed_tangent.get());
      if (vertex_constraints)
        newton.set_vertex_constraints(vertex_constraints.get(),
                                      &prescribed,
                                      scene->effects.active_set_limit());
      try
        {
          last_report = newton.solve(
            motion, u, timer(), progress, description, hint, body_force);
        }
      catch (const Error &)
        {
          // How far it got stays readable (report().load_reached).
          last_report = newton.report_so_far();
          throw;
        }
      vertex_values(u, displacement);

      set_iterations(last_report.newton_iterations);
      set_residual(last_report.final_residual);
      if (last_report.started_from_guess)
        add_detail("initial guess", "first step from it");
      add_detail("load steps", last_report.load_steps);
      add_detail("cut-backs", last_report.cutbacks);
      if (last_report.damped_predictors > 0)
        add_detail("damped predictors", last_report.damped_predictors);
      if (last_report.indefinite_solves > 0)
        add_detail("indefinite tangents solved by LU",
                   last_report.indefinite_solves);
      if (last_report.secant_fallbacks > 0)
        add_detail("secant predictors refused", last_report.secant_fallbacks);
      if (vertex_constraints)
        add_detail("contact constraints holding",
                   vertex_constraints->n_holding());
      std::string per_step;
      for (const unsigned int i : last_report.iterations_per_step)
        per_step += (per_step.empty() ? "" : "/") + std::to_string(i);
      add_detail("Newton iterations per step", per_step);
      add_detail("linear iterations", last_report.linear_iterations);
      if (solver_parameters.method != "direct")
        add_detail("AMG rebuilds", last_report.amg_rebuilds);
    }

    const Vector<double> *
    NonlinearElasticity::guess_in_model_numbering(const Vector<double> *guess,
                                                  Vector<double> &) const
    {
      return guess;
    }

    bool
    NonlinearElasticity::runs_without_scene_cells() const
    {
      return why_not_on_ranks_by_parameters().empty();
    }

    std::string
    NonlinearElasticity::why_not_on_ranks() const
    {
      if (scene->has_vertex_constraints())
        return "vertex constraints: whole on every rank";
      return why_not_on_ranks_by_parameters();
    }

    std::string
    NonlinearElasticity::why_not_on_ranks_by_parameters() const
    {
      if (solver_parameters.method != "cg amg")
        return "Solver '" + solver_parameters.method +
               "': whole on every rank; 'cg amg' is distributed";
      if (newton_parameters.corrector ==
          LoadSteppedNewton::Parameters::Corrector::kinsol)
        return "KINSOL: whole on every rank";
      if (newton_parameters.indefinite_lu)
        return "LU on indefinite tangents: whole on every rank";
      // Each load step's stability test is a Cholesky factorisation.
      if (law == MaterialLaw::Law::st_venant_kirchhoff)
        return "St. Venant-Kirchhoff's stability test: whole on every rank";
      return "";
    }

    bool
    NonlinearElasticity::evaluate_on_ranks(const Vector<double> &,
                                           Vector<double> &,
                                           const bool) const
    {
      AssertThrow(false, ExcMessage(model_name + " does not run on ranks."));
      return false;
    }

    bool
    NonlinearElasticity::end_evaluation_on_ranks(Vector<double> &forces,
                                                 unsigned int    refused) const
    {
      distributed_tangent->end_assembly(forces);
      refused = Utilities::MPI::min(refused, communicator);
      if (refused != numbers::invalid_unsigned_int)
        {
          refusal = describe_cell(refused);
          return false;
        }
      return true;
    }

    std::string
    NonlinearElasticity::describe_cell(const unsigned int cell_index) const
    {
      // A rank without the scene's cells (rank 0 has them, and speaks).
      if (!scene->has_cells())
        return " (cell " + std::to_string(cell_index) + ")";
      std::ostringstream where;
      const auto         cell =
        std::next(scene->triangulation.begin_active(), cell_index);
      std::set<std::string> touched;
      const auto           &segment_of = scene->vertex_segment();
      for (const unsigned int v : cell->vertex_indices())
        if (segment_of[cell->vertex_index(v)] < scene->segments.size())
          touched.insert(
            scene->segments[segment_of[cell->vertex_index(v)]].name);
      where << " (" << Mesh::cell_description(scene->cell_name, cell_index)
            << " at (" << cell->center() << "), join points of";
      if (touched.empty())
        where << " no segment";
      for (const auto &name : touched)
        where << " '" << name << "'";
      where << ")";
      return where.str();
    }

    const std::string &
    NonlinearElasticity::last_refusal() const
    {
      return refusal;
    }

    const SparsityPattern &
    NonlinearElasticity::sparsity_pattern() const
    {
      return sparsity;
    }

    unsigned int
    NonlinearElasticity::n_dofs() const
    {
      return is_join.size();
    }

    const LoadSteppedNewton::Report &
    NonlinearElasticity::report() const
    {
      return last_report;
    }
  } // namespace Models
} // namespace softface

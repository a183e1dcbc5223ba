#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <softface/fe/elasticity_amg.h>
#include <softface/core/error.h>
#include <softface/fe/linear_elasticity.h>
#include <softface/core/mesh.h>
#include <softface/models/nonlinear_fem.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace Models
  {
    void
    NonlinearFEM::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Material law",
                        "neo-hooke",
                        Patterns::Selection(
                          "st venant-kirchhoff|neo-hooke|linear"),
                        "'st venant-kirchhoff' (the seed's, and CalculiX's "
                        "*ELASTIC with NLGEOM; softens under strong "
                        "compression) or compressible 'neo-hooke' (stiffens "
                        "under compression). 'linear' solves linear FEM's "
                        "small-strain equations with this model's machinery: "
                        "with 'Polynomial degree = 2' it gives linear "
                        "elasticity's answer on the reference discretisation. "
                        "Lame parameters from Young's modulus and Poisson's "
                        "ratio as for the linear models.");
      prm.declare_entry("Solver",
                        "cg amg",
                        Patterns::Selection("direct|cg amg|gmres amg"),
                        "Linear solver of each Newton iteration: 'direct' "
                        "(CHOLMOD, ordering reused), 'cg amg' or 'gmres amg' "
                        "(Trilinos ML on the linear stiffness; rebuilt on the "
                        "tangent when a solve gets slow). CG stops when it "
                        "meets negative curvature (the tangent is not "
                        "positive definite) and the load step is cut back, "
                        "as when the direct solver's factorisation fails.");
      prm.declare_entry("Initial load increment",
                        "1",
                        Patterns::Double(0., 1.),
                        "Fraction of the planned motion tried in the first "
                        "load step; later steps grow after quick convergence "
                        "and are halved after a failure.");
      prm.declare_entry("Minimum load increment",
                        "0.001",
                        Patterns::Double(0., 1.),
                        "A step that still fails at this increment ends the "
                        "solve with an error giving the load reached, the "
                        "residual and the reason.");
      prm.declare_entry("Maximum Newton iterations",
                        "20",
                        Patterns::Integer(1),
                        "Newton iterations per load step before it counts as "
                        "failed.");
      prm.declare_entry("Residual tolerance",
                        "1e-10",
                        Patterns::Double(0., 1.),
                        "Newton stops when the free DoFs' residual force is "
                        "below this fraction of the largest unbalanced force "
                        "a load step started with.");
      prm.declare_entry("Linear tolerance",
                        "1e-6",
                        Patterns::Double(0., 1.),
                        "Relative residual of the iterative linear solves "
                        "inside Newton.");
      prm.declare_entry("AMG rebuild iterations",
                        "100",
                        Patterns::Integer(1),
                        "With 'cg amg' or 'gmres amg': when a linear solve "
                        "takes more iterations than this, ML is rebuilt on "
                        "the current tangent for the following solves; a "
                        "solve still running at twice this many is "
                        "continued with ML rebuilt at once.");
      prm.declare_entry("Polynomial degree",
                        "1",
                        Patterns::Integer(1, 2),
                        "1: P1 tetrahedra on the shared DoF layout (closed-form "
                        "forces and tangent). 2: quadratic tetrahedra on a "
                        "layout of the model's own (forces and tangent by "
                        "quadrature), about eight times the DoFs: the "
                        "converged reference of the accuracy benchmark. The "
                        "result table shows its vertex values.");
    }

    void
    NonlinearFEM::parse_parameters(ParameterHandler &prm)
    {
      law         = Hyperelasticity::law_from_name(prm.get("Material law"));
      solver_name = prm.get("Solver");
      initial_increment     = prm.get_double("Initial load increment");
      minimum_increment     = prm.get_double("Minimum load increment");
      max_newton_iterations = prm.get_integer("Maximum Newton iterations");
      residual_tolerance    = prm.get_double("Residual tolerance");
      linear_tolerance      = prm.get_double("Linear tolerance");
      degree                = prm.get_integer("Polynomial degree");
      amg_rebuild_iterations = prm.get_integer("AMG rebuild iterations");
      if (!(initial_increment > 0.))
        throw Error(
          "nonlinear fem: 'Initial load increment' must be positive.");
    }

    void
    NonlinearFEM::set_options(const std::string &law_name,
                              const std::string &solver,
                              const double       increment,
                              const unsigned int polynomial_degree)
    {
      degree            = polynomial_degree;
      law               = Hyperelasticity::law_from_name(law_name);
      solver_name       = solver;
      initial_increment = increment;
    }

    void
    NonlinearFEM::setup(const Scene &scene_in)
    {
      scene = &scene_in;
      stats = Statistics();
      Timer timer;
      if (degree == 2)
        {
          setup_quadratic(timer);
          return;
        }
      is_join = scene->join_dofs();

      // Reference shape gradients and volume of every tetrahedron.
      cell_dofs.clear();
      cell_gradients.clear();
      cell_volumes.clear();
      for (const auto &cell : scene->triangulation.active_cell_iterators())
        {
          const auto   x = LinearElasticity::cell_vertices(cell);
          Tensor<2, 3> J;
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int d = 0; d < 3; ++d)
              J[d][k] = x[k + 1][d] - x[0][d];
          const Tensor<2, 3>          J_inverse = invert(J);
          std::array<Tensor<1, 3>, 4> grad;
          for (unsigned int a = 1; a < 4; ++a)
            grad[a] = J_inverse[a - 1];
          grad[0] = -(grad[1] + grad[2] + grad[3]);
          cell_gradients.push_back(grad);
          cell_volumes.push_back(determinant(J) / 6.);
          std::array<types::global_dof_index, 12> dofs;
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              dofs[3 * a + i] = scene->vertex_dofs()[cell->vertex_index(a)][i];
          cell_dofs.push_back(dofs);
        }

      stats.phases.emplace_back("cells", timer.wall_time());
      LinearElasticity::make_sparsity_pattern(*scene, sparsity);
      tangent.reinit(sparsity);

      // Where each of a cell's 144 tangent entries lives in the matrix's
      // value array: every Newton iteration adds to them directly instead of
      // searching the rows (which took most of the assembly time).
      cell_entry_positions.resize(144 * cell_dofs.size());
      for (unsigned int c = 0; c < cell_dofs.size(); ++c)
        {
          const auto &dofs  = cell_dofs[c];
          const auto  order = LinearElasticity::sorted_order(dofs);
          for (unsigned int r = 0; r < 12; ++r)
            {
              // A square pattern stores the diagonal first, then the other
              // columns ascending: one merge along the row finds all twelve.
              const auto row      = dofs[r];
              auto       entry    = sparsity.begin(row);
              const auto diagonal = entry->global_index();
              ++entry;
              for (const unsigned int q : order)
                {
                  if (dofs[q] == row)
                    {
                      cell_entry_positions[144 * c + 12 * r + q] = diagonal;
                      continue;
                    }
                  while (entry->column() < dofs[q])
                    ++entry;
                  Assert(entry->column() == dofs[q], ExcInternalError());
                  cell_entry_positions[144 * c + 12 * r + q] =
                    entry->global_index();
                }
            }
        }
      stats.phases.emplace_back("positions", timer.wall_time());
      if (solver_name != "direct")
        {
          // The preconditioner is built once, on the linear stiffness (the
          // tangent at rest): close enough to every later tangent.
          LinearElasticity::assemble_stiffness(*scene, tangent);
          LinearElasticity::eliminate_join_dofs(scene->join_dofs(), tangent);
          amg_matrix.reinit(tangent);
          build_amg();
        }
      stats.setup_time = timer.wall_time();
      stats.phases.emplace_back("setup", stats.setup_time);
    }

    void
    NonlinearFEM::setup_quadratic(Timer &timer)
    {
      quadratic_fe   = std::make_unique<FESystem<3>>(FE_SimplexP<3>(2), 3);
      quadratic_dofs = std::make_unique<DoFHandler<3>>(scene->triangulation);
      quadratic_dofs->distribute_dofs(*quadratic_fe);
      const unsigned int n = quadratic_dofs->n_dofs();

      // Join DoFs: every DoF of a segment's cell and of its boundary faces.
      // Their prescribed value is the linear interpolation of the cell's
      // vertex values, exact for a rigid (affine) motion; the support
      // points serve ML's rigid-body modes.
      const FiniteElement<3> &fe = *quadratic_fe;
      const auto             &unit_points = fe.get_unit_support_points();
      const unsigned int      n_cell      = fe.n_dofs_per_cell();
      is_join.assign(n, false);
      from_vertex_dofs.resize(n);
      at_vertex_dof.assign(scene->dof_handler.n_dofs(),
                           numbers::invalid_dof_index);
      dof_points.resize(n);
      dof_component.resize(n);
      std::vector<types::global_dof_index> dofs(n_cell), face_dofs;
      for (const auto &cell : quadratic_dofs->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          bool bone_cell = false;
          for (const auto &segment : scene->segments)
            bone_cell |= segment.material_ids.count(cell->material_id()) > 0;
          for (unsigned int i = 0; i < n_cell; ++i)
            {
              const unsigned int c  = fe.system_to_component_index(i).first;
              const Point<3>    &xi = unit_points[i];
              const std::array<double, 4> weight = {
                {1. - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]}};
              Point<3> x;
              for (unsigned int a = 0; a < 4; ++a)
                {
                  const auto vertex_dof =
                    scene->vertex_dofs()[cell->vertex_index(a)][c];
                  from_vertex_dofs[dofs[i]][a] = {vertex_dof, weight[a]};
                  x += weight[a] * cell->vertex(a);
                  if (weight[a] == 1.)
                    {
                      at_vertex_dof[vertex_dof] = dofs[i];
                      if (scene->join_dofs()[vertex_dof])
                        is_join[dofs[i]] = true;
                    }
                }
              dof_points[dofs[i]]    = x;
              dof_component[dofs[i]] = c;
              if (bone_cell)
                is_join[dofs[i]] = true;
            }
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              for (const auto &segment : scene->segments)
                if (segment.boundary_ids.count(cell->face(f)->boundary_id()))
                  {
                    face_dofs.resize(fe.n_dofs_per_face(f));
                    cell->face(f)->get_dof_indices(face_dofs);
                    for (const auto i : face_dofs)
                      is_join[i] = true;
                  }
        }
      stats.phases.emplace_back("cells", timer.wall_time());

      DynamicSparsityPattern dsp(n, n);
      DoFTools::make_sparsity_pattern(*quadratic_dofs, dsp);
      sparsity.copy_from(dsp);
      tangent.reinit(sparsity);
      stats.phases.emplace_back("positions", timer.wall_time());
      if (solver_name != "direct")
        {
          Vector<double> zero(n), forces(n);
          evaluate(zero, forces, &tangent);
          LinearElasticity::eliminate_join_dofs(is_join, tangent);
          amg_matrix.reinit(tangent);
          build_amg();
        }
      stats.setup_time = timer.wall_time();
      stats.phases.emplace_back("setup", stats.setup_time);
      stats.details.clear();
      stats.details.emplace_back("degree", "2");
      stats.details.emplace_back("DoFs", std::to_string(n));
    }

    void
    NonlinearFEM::build_amg()
    {
      if (degree == 1)
        initialize_elasticity_amg(*scene, amg_matrix, 0.02, 2, amg);
      else
        initialize_elasticity_amg(
          dof_points, dof_component, amg_matrix, 0.02, 2, amg);
    }

    std::pair<const DoFHandler<3> *, const Vector<double> *>
    NonlinearFEM::displacement_field() const
    {
      if (degree == 2 && quadratic_solution.size() > 0)
        return {quadratic_dofs.get(), &quadratic_solution};
      return {nullptr, nullptr};
    }

    unsigned int
    NonlinearFEM::n_dofs() const
    {
      return is_join.size();
    }

    bool
    NonlinearFEM::evaluate(const Vector<double> &u,
                           Vector<double>       &forces,
                           SparseMatrix<double> *tangent_matrix) const
    {
      const double lambda = scene->material.lambda(), mu = scene->material.mu();
      if (degree == 2)
        {
          // 14-point rule: exact for the quadratic element's linear
          // stiffness and accurate for its nonlinear terms.
          return Hyperelasticity::assemble(law,
                                           lambda,
                                           mu,
                                           scene->mapping,
                                           *quadratic_dofs,
                                           QGaussSimplex<3>(3),
                                           u,
                                           forces,
                                           tangent_matrix);
        }
      forces.reinit(u.size());
      double *values = nullptr;
      if (tangent_matrix != nullptr)
        {
          Assert(&tangent_matrix->get_sparsity_pattern() == &sparsity,
                 ExcMessage("The tangent must live on sparsity_pattern()."));
          *tangent_matrix = 0;
          // SparseMatrix keeps its values in one array in the order of the
          // sparsity pattern's entries; a square matrix stores the diagonal
          // first in each row, so entry (0,0) is the start of that array.
          values = &tangent_matrix->diag_element(0);
        }
      Hyperelasticity::CellResponse response;
      std::array<Tensor<1, 3>, 4>   u_cell;
      for (unsigned int c = 0; c < cell_dofs.size(); ++c)
        {
          const auto &dofs = cell_dofs[c];
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              u_cell[a][i] = u[dofs[3 * a + i]];
          if (!Hyperelasticity::cell_response(law,
                                              lambda,
                                              mu,
                                              cell_gradients[c],
                                              cell_volumes[c],
                                              u_cell,
                                              tangent_matrix != nullptr,
                                              response))
            return false;
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              forces[dofs[3 * a + i]] += response.force[a][i];
          if (values != nullptr)
            {
              const unsigned int *position = &cell_entry_positions[144 * c];
              for (unsigned int a = 0; a < 4; ++a)
                for (unsigned int i = 0; i < 3; ++i)
                  for (unsigned int b = 0; b < 4; ++b)
                    for (unsigned int j = 0; j < 3; ++j)
                      values[*position++] += response.tangent[a][b][i][j];
            }
        }
      return true;
    }

    double
    NonlinearFEM::free_norm(const Vector<double> &v) const
    {
      double sum = 0.;
      for (unsigned int i = 0; i < v.size(); ++i)
        if (!is_join[i])
          sum += v[i] * v[i];
      return std::sqrt(sum);
    }

    bool
    NonlinearFEM::linear_solve(const Vector<double> &rhs,
                               Vector<double>       &solution,
                               std::string          &reason)
    {
      Timer timer;
      solution.reinit(rhs.size());
      bool ok = true;
      if (solver_name == "direct")
        {
          ok = cholesky.refactorize(tangent);
          if (ok)
            cholesky.solve(rhs, solution);
          else
            reason = "the tangent is not positive definite";
          ++last_report.linear_iterations;
        }
      else
        {
          // ML was built on the tangent at rest (or at the last rebuild);
          // far from rest (large motions, compressed tissue) it loses its
          // grip and CG needs hundreds of iterations. A solve that passes
          // twice the rebuild limit is therefore continued, from where it
          // got to, with ML rebuilt on the current tangent; a solve over the
          // limit also triggers a rebuild for the next ones.
          const unsigned int max_iterations = 2000;
          const unsigned int first_attempt =
            std::min(max_iterations, 2 * amg_rebuild_iterations);
          unsigned int iterations         = 0;
          bool         negative_curvature = false;
          const auto   attempt            = [&](const unsigned int limit) {
            SolverControl control(limit,
                                  linear_tolerance * rhs.l2_norm(),
                                  false,
                                  false);
            bool converged = true;
            try
              {
                if (solver_name == "cg amg")
                  {
                    // A step length alpha <= 0 means p^T K p <= 0: the
                    // tangent is not positive definite, where CG has no
                    // answer and used to run to its limit. Stop at once
                    // (the signal reports alpha one iteration late) and let
                    // Newton cut the load back, as the direct solver does.
                    SolverCG<Vector<double>> cg(control);
                    cg.connect_coefficients_slot(
                      [&](const double alpha, const double) {
                        if (!(alpha > 0.))
                          negative_curvature = true;
                      });
                    cg.connect([&](const unsigned int,
                                   const double,
                                   const Vector<double> &) {
                      return negative_curvature ? SolverControl::failure :
                                                               SolverControl::success;
                    });
                    cg.solve(tangent, solution, rhs, amg);
                  }
                else
                  {
                    SolverGMRES<Vector<double>> gmres(
                      control,
                      SolverGMRES<Vector<double>>::AdditionalData(52));
                    gmres.solve(tangent, solution, rhs, amg);
                  }
              }
            catch (const std::exception &e)
              {
                converged = false;
              }
            iterations += control.last_step();
            return converged;
          };
          const auto rebuild = [&]() {
            amg_matrix.reinit(tangent);
            build_amg();
            ++last_report.amg_rebuilds;
          };
          ok = attempt(first_attempt);
          if (!ok && !negative_curvature && first_attempt < max_iterations)
            {
              rebuild();
              ok = attempt(max_iterations - first_attempt);
            }
          else if (iterations > amg_rebuild_iterations)
            rebuild();
          if (negative_curvature)
            reason = "the tangent is not positive definite (CG found "
                     "negative curvature after " +
                     std::to_string(iterations) + " iterations)";
          else if (!ok)
            reason = solver_name + " did not converge (" +
                     std::to_string(iterations) + " iterations)";
          last_report.linear_iterations += iterations;
        }
      time_linear += timer.wall_time();
      return ok;
    }

    NonlinearFEM::StepResult
    NonlinearFEM::newton(Vector<double> &u, const Vector<double> &target)
    {
      const unsigned int n = u.size();
      StepResult               result;

      // The first iteration carries the join points to the step's target.
      Vector<double> join_increment(n);
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          join_increment[i] = target[i] - u[i];

      Vector<double> forces(n), rhs(n), du(n), trial(n), trial_forces(n);
      // The accepted line-search point was evaluated with its tangent, so
      // the next iteration starts from it without assembling again.
      bool evaluated = false;
      for (unsigned int it = 0; it <= max_newton_iterations; ++it)
        {
          Timer              iteration_timer;
          const unsigned int linear_before = last_report.linear_iterations;
          Timer              assembly;
          const bool first = (it == 0);
          if (!evaluated && !evaluate(u, forces, &tangent))
            {
              result.reason = "a tetrahedron is inverted";
              return result;
            }
          const double residual = free_norm(forces);
          result.residual       = residual / std::max(reference_force, 1e-300);
          if (!first && residual <= residual_tolerance * reference_force)
            {
              result.converged = true;
              return result;
            }
          if (it == max_newton_iterations)
            break;

          // rhs = -R - K d on the free rows, K_jj d_j on the join rows.
          tangent.vmult(rhs, join_increment);
          rhs += forces;
          rhs *= -1.;
          LinearElasticity::eliminate_join_dofs(is_join, tangent);
          for (unsigned int i = 0; i < n; ++i)
            if (is_join[i])
              rhs[i] = tangent.diag_element(i) * join_increment[i];
          if (first)
            {
              reference_force = std::max(reference_force, free_norm(rhs));
              if (reference_force == 0.)
                {
                  result.converged = true;
                  return result;
                }
            }
          time_assembly += assembly.wall_time();

          if (!linear_solve(rhs, du, result.reason))
            return result;
          ++result.iterations;
          for (unsigned int i = 0; i < n; ++i)
            if (is_join[i])
              du[i] = join_increment[i];

          // Backtracking on the residual norm; the predictor (which moves
          // the join points) is taken whole or the step fails.
          bool accepted = false;
          for (double alpha = 1.; alpha > 1. / 64 && !accepted; alpha /= 2)
            {
              trial = u;
              trial.add(alpha, du);
              Timer      line_search;
              const bool valid = evaluate(trial, trial_forces, &tangent);
              time_assembly += line_search.wall_time();
              if (valid && (first || free_norm(trial_forces) <=
                                       (1. - 1e-4 * alpha) * residual))
                accepted = true;
              if (first)
                break;
            }
          if (!accepted)
            {
              result.reason = first ? "the predictor inverts a tetrahedron" :
                                      "the line search found no descent";
              return result;
            }
          u.swap(trial);
          forces.swap(trial_forces);
          evaluated      = true;
          join_increment = 0.;

          // Large (quadratic reference) solves take minutes: say where they
          // are once an iteration is slow enough for anyone to wonder.
          if (progress != nullptr && iteration_timer.wall_time() > 5.)
            {
              std::ostringstream line;
              line << "        Newton iteration " << result.iterations << ": ";
              if (first)
                line << "predictor (join points moved), ";
              else
                line << "relative residual before " << std::setprecision(2)
                     << result.residual << ", ";
              line << last_report.linear_iterations - linear_before
                   << " linear iterations, " << std::fixed
                   << std::setprecision(1) << iteration_timer.wall_time()
                   << " s\n";
              *progress << line.str() << std::flush;
            }
        }
      result.reason = "no convergence in " +
                      std::to_string(max_newton_iterations) + " iterations";
      return result;
    }

    void
    NonlinearFEM::solve(const Vector<double> &prescribed,
                        Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("NonlinearFEM::setup() first."));
      Timer              timer;
      const unsigned int n = is_join.size();
      last_report          = Report();
      reference_force      = 0.;
      time_assembly = time_linear = 0.;

      Vector<double> join_motion(n);
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          {
            if (degree == 1)
              join_motion[i] = prescribed[i];
            else
              for (const auto &[vertex_dof, weight] : from_vertex_dofs[i])
                join_motion[i] += weight * prescribed[vertex_dof];
          }

      Vector<double>  u_quadratic;
      Vector<double> &u = (degree == 1 ? displacement : u_quadratic);
      u.reinit(n);
      Vector<double> converged = u, target(n);
      double         load = 0., increment = initial_increment;
      while (load < 1.)
        {
          const double next = std::min(1., load + increment);
          target.equ(next, join_motion);
          const StepResult step = newton(u, target);
          if (step.converged)
            {
              load      = next;
              converged = u;
              ++last_report.load_steps;
              last_report.newton_iterations += step.iterations;
              last_report.iterations_per_step.push_back(step.iterations);
              last_report.final_residual = step.residual;
              if (progress != nullptr)
                {
                  std::ostringstream line;
                  line << "      load step " << last_report.load_steps
                       << ": load " << load << ", " << step.iterations
                       << " Newton iterations, relative residual "
                       << std::setprecision(2) << step.residual << '\n';
                  *progress << line.str() << std::flush;
                }
              if (step.iterations <= 4)
                increment *= 2.;
              increment = std::min(increment, 1. - load);
              if (!std::isfinite(u.l2_norm()))
                throw Error("nonlinear fem: the displacement became NaN.");
            }
          else
            {
              u = converged;
              ++last_report.cutbacks;
              if (progress != nullptr)
                {
                  std::ostringstream line;
                  line << "      load " << next << " failed (" << step.reason
                       << "), cutting back\n";
                  *progress << line.str() << std::flush;
                }
              last_report.newton_iterations += step.iterations;
              increment /= 2.;
              if (increment < minimum_increment)
                {
                  std::ostringstream m;
                  m << "nonlinear fem (" << Hyperelasticity::law_name(law)
                    << ", " << solver_name << "): load step "
                    << last_report.load_steps + 1 << " failed at load " << next
                    << " of the planning: " << step.reason
                    << " (relative residual " << step.residual
                    << "); the increment fell below " << minimum_increment
                    << " after " << last_report.cutbacks
                    << " cut-backs. Last converged load: " << load << ".";
                  if (law == Hyperelasticity::Law::st_venant_kirchhoff)
                    m << " St. Venant-Kirchhoff softens under strong "
                         "compression and may have no equilibrium here; "
                         "'Material law = neo-hooke' does.";
                  throw Error(m.str());
                }
            }
        }

      if (degree == 2)
        {
          quadratic_solution = u;
          displacement.reinit(scene->dof_handler.n_dofs());
          for (unsigned int i = 0; i < displacement.size(); ++i)
            if (at_vertex_dof[i] != numbers::invalid_dof_index)
              displacement[i] = u[at_vertex_dof[i]];
        }

      stats.iterations = last_report.newton_iterations;
      stats.residual   = last_report.final_residual;
      stats.solve_time = timer.wall_time();
      stats.phases.resize(std::min<std::size_t>(stats.phases.size(), 3));
      const bool quadratic = (degree == 2);
      stats.phases.emplace_back("assembly", time_assembly);
      stats.phases.emplace_back("linear solves", time_linear);
      stats.details.clear();
      if (quadratic)
        {
          stats.details.emplace_back("degree", "2");
          stats.details.emplace_back("DoFs", std::to_string(n));
        }
      stats.details.emplace_back("load steps",
                                 std::to_string(last_report.load_steps));
      stats.details.emplace_back("cut-backs",
                                 std::to_string(last_report.cutbacks));
      std::string per_step;
      for (const unsigned int i : last_report.iterations_per_step)
        per_step += (per_step.empty() ? "" : "/") + std::to_string(i);
      stats.details.emplace_back("Newton iterations per step", per_step);
      stats.details.emplace_back("linear iterations",
                                 std::to_string(last_report.linear_iterations));
      if (solver_name != "direct")
        stats.details.emplace_back("AMG rebuilds",
                                   std::to_string(last_report.amg_rebuilds));
    }

    const SparsityPattern &
    NonlinearFEM::sparsity_pattern() const
    {
      return sparsity;
    }

    const NonlinearFEM::Report &
    NonlinearFEM::report() const
    {
      return last_report;
    }

    SOFTFACE_REGISTER_MODEL(NonlinearFEM,
                            "nonlinear fem",
                            "Large-deformation elasticity on P1 tetrahedra "
                            "(St. Venant-Kirchhoff or Neo-Hooke), Newton with "
                            "line search and load-step cut-back.")
  } // namespace Models
} // namespace softface

// The mass tensor model (models; Mollemans et al. 2007, Sec. 2.3): Cotin's
// tensors from the shared P1 stiffness kernel, the paper's local static update
// with its local dynamic stop criterion and active set, and the precision
// against the converged answer of the same equations.

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <softface/core/displacement.h>
#include <softface/core/error.h>
#include <softface/core/release.h>
#include <softface/core/tetrahedron.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/point_block_pattern.h>
#include <softface/models/mass_tensor.h>
#include <softface/models/point_constraints.h>
#include <softface/models/point_exchange.h>
#include <softface/models/point_sweeps.h>
#include <softface/models/stop_distance_check.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

namespace softface
{
  namespace Models
  {
    namespace
    {
      // "auto" or a number from 0.5 to 2: checked by ParameterHandler, so a
      // bad value is reported with its file and line.
      class AutoOrFactor : public Patterns::PatternBase
      {
      public:
        bool
        match(const std::string &text) const override
        {
          return text == "auto" || Patterns::Double(0.5, 2.).match(text);
        }
        std::string
        description(const OutputStyle = Machine) const override
        {
          return "[auto or a number from 0.5 to 2]";
        }
        std::unique_ptr<PatternBase>
        clone() const override
        {
          return std::make_unique<AutoOrFactor>();
        }
      };
    } // namespace

    MassTensor::MassTensor() = default;

    MassTensor::~MassTensor() = default;

    void
    MassTensor::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry(
        "Ordering",
        "gauss-seidel",
        Patterns::Selection("gauss-seidel|jacobi"),
        "Order of the local updates (Mollemans et al. 2007, eq. 12): "
        "'gauss-seidel' uses every new value at once, "
        "'jacobi' only values from the previous sweep.");
      prm.declare_entry(
        "Relaxation factor",
        "auto",
        AutoOrFactor(),
        "Each update moves a point by this factor times the change eq. 12 of "
        "Mollemans et al. 2007 asks for. 'auto': 1.8 with Gauss-Seidel order "
        "(over-relaxation, SOR: on a 106k-tetrahedron cube with "
        "traction-free faces and a rotated off-centre bone it needs 10 times "
        "fewer point updates than the paper's factor 1 for the same distance "
        "to the answer; SOR converges for any factor below 2 on these "
        "equations), 1 with Jacobi order. "
        "Else a number from 0.5 to 2: 1 is the paper's scheme; below 1 it "
        "damps Jacobi order (which diverges undamped on many meshes; the "
        "stop criterion then looks at the whole change, not the damped "
        "step); below 0.5 the updates would shrink so slowly that the stop "
        "criterion would end far from the answer (0.1: 0.54 mm on the 35k "
        "cube; 0.01: at once).");
      prm.declare_entry(
        "Stop gradient threshold",
        "0.001",
        Patterns::Double(0.),
        "A point stops when the mean length of its last "
        "'Gradient window' updates falls below this (mm per "
        "sweep; Mollemans et al. 2007, Sec. 2.3.3 and Table 1). 0 runs to full "
        "convergence ('Convergence tolerance').");
      prm.declare_entry(
        "Stop distance",
        "0.1",
        Patterns::Double(0.),
        "The stop criterion of Mollemans et al. 2007 alone can stop far from "
        "the answer when "
        "the sweeps converge slowly (0.40 mm on a 106k cube with "
        "traction-free faces and a rotated off-centre bone: each sweep "
        "changes little long before the answer is near). So when it "
        "says stop, the largest step of each sweep since the sweeps "
        "(re)started gives the rate rho at which the steps shrink (over "
        "the second half of those sweeps: the slow modes' rate creeps up "
        "over hundreds of sweeps), and the solve ends only if the "
        "distance left that this extrapolates, largest recent step times "
        "rho / (1 - rho), is below this (mm). Else the gradient threshold "
        "is lowered to what the rate asks for and every free point sweeps "
        "on. A stop proposed before 4 'Gradient window's of sweeps is "
        "postponed until the rate can be measured. Where the steps do not "
        "shrink (rho >= 1) the paper's criterion decides, with a warning. "
        "0: the paper's "
        "criterion alone.");
      prm.declare_entry("Gradient window",
                        "10",
                        Patterns::Integer(1, 1000),
                        "Number of a point's last updates whose mean is its "
                        "gradient.");
      prm.declare_entry("Active set",
                        "true",
                        Patterns::Bool(),
                        "Visit only points whose force can have changed: "
                        "those not yet stopped and the neighbours of points "
                        "that moved by more than the threshold. false visits "
                        "every free point in every sweep until all have "
                        "stopped.");
      prm.declare_entry("Maximum sweeps",
                        "100000",
                        Patterns::Integer(1),
                        "A solve that needs more sweeps stops with an error "
                        "stating the largest gradient reached.");
      prm.declare_entry("Convergence tolerance",
                        "1e-9",
                        Patterns::Double(0.),
                        "Gradient (mm per sweep) below which a point counts "
                        "as converged when the stop threshold is 0.");
      prm.declare_entry(
        "Report precision",
        "false",
        Patterns::Bool(),
        "Also compute the fully converged answer of the same "
        "equations (by the sparse direct solver) and report "
        "the largest and mean distance of a free point to it "
        "(the minimal and mean precision of Mollemans et al. 2007, Table 1). "
        "When Models/Models also lists linear fem (which "
        "then runs before the mass tensor model, wherever it "
        "is listed), its answer is that answer, to its "
        "solver's tolerance, and is used instead.");
      prm.declare_entry(
        "Precision history file",
        "",
        Patterns::Anything(),
        "If set, solve the converged answer first and write, after every "
        "sweep, the largest and mean distance of a free point to it and the "
        "largest gradient (CSV: sweep,precision_max,precision_mean,"
        "max_gradient,active_points): the precision study of "
        "Mollemans et al. 2007 (Sec. 2.3.5, Fig. 1). Relative to the working "
        "directory. Costs one pass "
        "over the points per sweep.");
    }

    void
    MassTensor::parse_parameters(ParameterHandler &prm)
    {
      gauss_seidel             = prm.get("Ordering") == "gauss-seidel";
      const std::string factor = prm.get("Relaxation factor");
      relaxation               = factor == "auto" ? 0. : std::stod(factor);
      stop_gradient_threshold  = prm.get_double("Stop gradient threshold");
      gradient_window          = prm.get_integer("Gradient window");
      use_active_set           = prm.get_bool("Active set");
      max_sweeps               = prm.get_integer("Maximum sweeps");
      convergence_tolerance    = prm.get_double("Convergence tolerance");
      stop_distance            = prm.get_double("Stop distance");
      report_precision         = prm.get_bool("Report precision");
      precision_history_file   = prm.get("Precision history file");
    }

    void
    MassTensor::set_scheme(const bool         gauss_seidel_order,
                           const double       threshold,
                           const unsigned int window,
                           const bool         active_set)
    {
      gauss_seidel            = gauss_seidel_order;
      stop_gradient_threshold = threshold;
      gradient_window         = window;
      use_active_set          = active_set;
    }

    void
    MassTensor::set_relaxation(const double factor)
    {
      relaxation = factor;
    }

    void
    MassTensor::set_stop_distance(const double distance)
    {
      stop_distance = distance;
    }

    double
    MassTensor::relaxation_factor() const
    {
      return relaxation > 0. ? relaxation : gauss_seidel ? 1.8 : 1.;
    }

    void
    MassTensor::set_report_precision(const bool report)
    {
      report_precision = report;
    }

    void
    MassTensor::set_precision_history_file(const std::string &filename)
    {
      precision_history_file = filename;
    }

    unsigned int
    MassTensor::honoured_effects() const
    {
      return SceneEffects::cell_materials | SceneEffects::body_forces |
             SceneEffects::free_vertex_constraints;
    }

    bool
    MassTensor::linear_in_motion(const Scene &scene) const
    {
      return !has_unilateral_contact(scene);
    }

    bool
    MassTensor::runs_without_scene_cells() const
    {
      return true;
    }

    std::string
    MassTensor::converged_equivalent() const
    {
      return "linear fem";
    }

    void
    MassTensor::do_setup(const Scene &scene_in)
    {
      scene           = &scene_in;
      converged_ready = false;
      converged_constraints.reset();
      release(whole_coupling);
      release(whole_diagonal);
      unsigned int n = 0;
      {
        const auto timed = phase("tensors");
        mesh = std::make_unique<PointMesh>(*scene, "mass tensor", communicator);
        n    = mesh->n_points();
        // A constrained update also moves its partner and reads the
        // partner's neighbours, further than a block's colour keeps apart:
        // such scenes sweep in plain order on one thread.
        colouring = !scene->has_vertex_constraints() ?
                      std::make_unique<BlockColouring>(n,
                                                       mesh->row_start,
                                                       mesh->neighbour) :
                      std::make_unique<BlockColouring>(n);
      }

      // On several MPI ranks each updates the points it owns,
      // and holds their rows only.
      exchange.reset();
      exchange = point_exchange(*scene, *colouring, *mesh);

      auto timed           = phase("tensors");
      first_row            = 0;
      unsigned int end_row = n;
      if (exchange)
        {
          first_row = exchange->first_owned_point();
          end_row   = first_row + exchange->n_owned_points();
        }
      first_entry = mesh->row_start[first_row];
      make_tensors(first_row, end_row, coupling, diagonal);

      diagonal_inverse.resize(diagonal.size());
      for (unsigned int j = 0; j < diagonal.size(); ++j)
        {
          Tensor<2, 3> D;
          for (unsigned int r = 0; r < 3; ++r)
            for (unsigned int s = 0; s < 3; ++s)
              D[r][s] = diagonal[j][3 * r + s];
          const Tensor<2, 3> D_inverse = invert(D);
          for (unsigned int r = 0; r < 3; ++r)
            for (unsigned int s = 0; s < 3; ++s)
              diagonal_inverse[j][3 * r + s] = D_inverse[r][s];
        }

      make_point_constraints(*scene, n, point_constraints, constraint_of_point);
      if (!point_constraints.empty() && !gauss_seidel)
        throw Error("mass tensor: vertex constraints (sliding contact, "
                    "separated lips) need 'Ordering = gauss-seidel'.");
      add_detail("colours", colouring->colours.size(), "");

      timed.stop();

      // This rank's tensors and the neighbour lists (every rank's).
      add_detail("tensor memory",
                 (coupling.size() * sizeof(Block) +
                  mesh->neighbour.size() * sizeof(unsigned int) +
                  diagonal.size() * 2 * sizeof(Block)) /
                   1048576.,
                 "MB");
    }

    void
    MassTensor::make_tensors(const unsigned int  first,
                             const unsigned int  end,
                             std::vector<Block> &coupling_rows,
                             std::vector<Block> &diagonal_rows) const
    {
      const std::size_t first_i = mesh->row_start[first];
      coupling_rows.assign(mesh->row_start[end] - first_i, Block{});
      diagonal_rows.assign(end - first, Block{});
      std::vector<Tensor<4, 3>> A; // one per tissue
      for (unsigned int t = 0; t < scene->n_tissues(); ++t)
        A.push_back(Elasticity::linear_tangent(scene->tissue(t).lame()));
      const auto held = [&](const unsigned int j) {
        return j >= first && j < end;
      };
      for (unsigned int c = 0; c < mesh->tetrahedra.size(); ++c)
        {
          const auto &p = mesh->tetrahedra[c];
          if (!held(p[0]) && !held(p[1]) && !held(p[2]) && !held(p[3]))
            continue;
          const Elasticity::CellMatrix K =
            Elasticity::p1_stiffness(Tetrahedron::geometry(mesh->vertices(c)),
                                     A[mesh->tissue[c]]);
          for (unsigned int a = 0; a < 4; ++a)
            if (held(p[a]))
              for (unsigned int b = 0; b < 4; ++b)
                {
                  Block *target =
                    (a == b) ?
                      &diagonal_rows[p[a] - first] :
                      &coupling_rows[mesh->edge_index(p[a], p[b]) - first_i];
                  for (unsigned int r = 0; r < 3; ++r)
                    for (unsigned int s = 0; s < 3; ++s)
                      (*target)[3 * r + s] += K[a][b][r][s];
                }
        }
    }

    void
    MassTensor::solve_converged(const Vector<double> &prescribed,
                                Vector<double>       &converged)
    {
      const auto         timed     = phase("converged answer", true);
      const auto        &row_start = mesh->row_start;
      const auto        &neighbour = mesh->neighbour;
      const auto        &is_free   = mesh->is_free;
      const unsigned int n         = mesh->n_points();
      // The whole tensors: on several MPI ranks this one holds its rows only
      // and makes the others once, for this diagnostic.
      if ((first_row != 0 || diagonal.size() != n) && whole_diagonal.empty())
        make_tensors(0, n, whole_coupling, whole_diagonal);
      const std::vector<Block> &all_coupling =
        whole_diagonal.empty() ? coupling : whole_coupling;
      const std::vector<Block> &all_diagonal =
        whole_diagonal.empty() ? diagonal : whole_diagonal;
      if (!converged_ready)
        {
          // The tensors are the blocks of one sparse matrix on the shared
          // layout; with the join DoFs eliminated it is factorised once.
          // (A rank without the scene's cells: the same pattern, from the
          // points' neighbours.)
          if (scene->has_cells())
            ConstrainedSystem::make_sparsity_pattern(*scene,
                                                     converged_sparsity);
          else
            PointBlockPattern(*mesh).make_sparsity(converged_sparsity);
          converged_matrix.reinit(converged_sparsity);
          for (unsigned int j = 0; j < n; ++j)
            for (unsigned int r = 0; r < 3; ++r)
              for (unsigned int s = 0; s < 3; ++s)
                {
                  converged_matrix.set(3 * j + r,
                                       3 * j + s,
                                       all_diagonal[j][3 * r + s]);
                  for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
                    converged_matrix.set(3 * j + r,
                                         3 * neighbour[i] + s,
                                         all_coupling[i][3 * r + s]);
                }
          if (!point_constraints.empty())
            {
              converged_unconstrained.reinit(converged_sparsity);
              converged_unconstrained.copy_from(converged_matrix);
              converged_constraints =
                std::make_unique<VertexConstraintSet>(*scene);
              converged_condensed_for.clear();
            }
          ConstrainedSystem::eliminate_join_dofs(scene->join_dofs(),
                                                 converged_matrix);
          LinearSolver::Parameters direct;
          direct.method = "direct";
          converged_solver.initialize(direct, *scene);
          if (point_constraints.empty() &&
              !converged_solver.set_matrix(converged_matrix))
            throw Error("mass tensor: the tensors' matrix is not positive "
                        "definite; no converged answer to compare with.");
          converged_ready = true;
        }
      // f_j - K_fj u_j on the free rows, K_jj u_j on the join rows.
      Vector<double> rhs(3 * n);
      if (scene->has_body_force())
        rhs = scene->effects.body_force;
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int r = 0; r < 3; ++r)
          {
            if (!is_free[j])
              {
                rhs[3 * j + r] = all_diagonal[j][4 * r] * prescribed[3 * j + r];
                continue;
              }
            for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
              if (!is_free[neighbour[i]])
                for (unsigned int s = 0; s < 3; ++s)
                  rhs[3 * j + r] -= all_coupling[i][3 * r + s] *
                                    prescribed[3 * neighbour[i] + s];
          }
      converged.reinit(3 * n);
      if (converged_constraints)
        {
          Vector<double> minus_forces(3 * n);
          if (scene->has_body_force())
            minus_forces -= scene->effects.body_force;
          converged_constraints->solve_with_active_set(
            converged_unconstrained,
            converged_matrix,
            converged_condensed,
            converged_condensed_for,
            converged_solver,
            rhs,
            prescribed,
            &minus_forces,
            scene->effects.active_set_limit(),
            "mass tensor (converged answer)",
            converged);
        }
      else
        converged_solver.solve(rhs, converged);
    }

    void
    MassTensor::local_optimum(const unsigned int  j,
                              const double *const u,
                              const double *const load,
                              double              opt[3]) const
    {
      const auto &row_start = mesh->row_start;
      const auto &neighbour = mesh->neighbour;
      double      f[3]      = {0., 0., 0.};
      if (load != nullptr)
        for (unsigned int r = 0; r < 3; ++r)
          f[r] = -load[3 * j + r];
      for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
        {
          const double *B  = coupling_of(i);
          const double *uk = u + 3 * neighbour[i];
          for (unsigned int r = 0; r < 3; ++r)
            f[r] +=
              B[3 * r] * uk[0] + B[3 * r + 1] * uk[1] + B[3 * r + 2] * uk[2];
        }
      const double *D = inverse_of(j);
      for (unsigned int r = 0; r < 3; ++r)
        opt[r] = -(D[3 * r] * f[0] + D[3 * r + 1] * f[1] + D[3 * r + 2] * f[2]);
    }

    void
    MassTensor::constrained_update(const unsigned int         j,
                                   double                     opt[3],
                                   double *const              u,
                                   const double *const        load,
                                   const Vector<double>      &prescribed,
                                   const double               threshold,
                                   PointSweeps               &sweeps,
                                   std::vector<unsigned int> &queued) const
    {
      // The local problem's minimiser under the constraint: the
      // unconstrained one moved along K_jj^-1 n (for a pair: both points,
      // by the multiplier that closes their gap).
      const PointConstraint &c   = point_constraints[constraint_of_point[j]];
      const auto             D_n = [&](const unsigned int k, double Dn[3]) {
        const double *D = inverse_of(k);
        for (unsigned int r = 0; r < 3; ++r)
          Dn[r] =
            D[3 * r] * c.n[0] + D[3 * r + 1] * c.n[1] + D[3 * r + 2] * c.n[2];
        return c.n[0] * Dn[0] + c.n[1] * Dn[1] + c.n[2] * Dn[2];
      };
      if (c.a == c.b)
        {
          double gap = 0.;
          for (unsigned int r = 0; r < 3; ++r)
            gap += c.n[r] * (opt[r] - prescribed[3 * j + r]);
          if (c.unilateral && gap >= 0.)
            return;
          double       Dn[3];
          const double nDn = D_n(j, Dn);
          for (unsigned int r = 0; r < 3; ++r)
            opt[r] -= gap / nDn * Dn[r];
          return;
        }
      const unsigned int other = (j == c.a ? c.b : c.a);
      double             opt_other[3];
      local_optimum(other, u, load, opt_other);
      double *opt_a = (j == c.a ? opt : opt_other);
      double *opt_b = (j == c.a ? opt_other : opt);
      double  gap   = 0.;
      for (unsigned int r = 0; r < 3; ++r)
        gap += c.n[r] * (opt_a[r] - opt_b[r]);
      if (!c.unilateral || gap < 0.)
        {
          double       Dn_a[3], Dn_b[3];
          const double lambda = -gap / (D_n(c.a, Dn_a) + D_n(c.b, Dn_b));
          for (unsigned int r = 0; r < 3; ++r)
            {
              opt_a[r] += lambda * Dn_a[r];
              opt_b[r] -= lambda * Dn_b[r];
            }
        }
      // The partner moves with the point (a block Gauss-Seidel update of
      // the pair: the point alone could pass through it), and its
      // neighbours feel it.
      double step = 0.;
      for (unsigned int r = 0; r < 3; ++r)
        {
          const double d = opt_other[r] - u[3 * other + r];
          u[3 * other + r] += d;
          step += d * d;
        }
      // Like any point whose step exceeds the threshold.
      // (With constraints every rank updates every free point.)
      if (use_active_set && step > threshold * threshold)
        {
          sweeps.queue(other, queued);
          sweeps.queue_neighbours(other, queued);
        }
    }

    /**
     * The mass tensor model's part of its sweeps (PointSweeps): the
     * paper's local update (eq. 12), relaxed, with each point's gradient over
     * its last W updates; after each sweep the paper's stop (Sec. 2.3.3),
     * checked by the distance left ('Stop distance'), and a row of the
     * precision history.
     */
    class MassTensor::LocalUpdates : public PointLocalUpdates
    {
    public:
      LocalUpdates(const MassTensor     &model,
                   PointSweeps          &sweeps,
                   const Vector<double> &prescribed,
                   Vector<double>       &displacement,
                   const Vector<double> &converged);

      // Inlined into the sweep's loop over a block's points (GCC would
      // call it once per point).
      DEAL_II_ALWAYS_INLINE bool
      update(const unsigned int         j,
             SweepTally                &tally,
             std::vector<unsigned int> &queued)
      {
        // The paper's eq. 12: u_j = K_jj^-1 (f_j - sum_k K_jk u_k)
        double f0 = 0., f1 = 0., f2 = 0.;
        if (load != nullptr)
          {
            f0 = -load[3 * j];
            f1 = -load[3 * j + 1];
            f2 = -load[3 * j + 2];
          }
        for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
          {
            const double *B  = rows_coupling[i - entry0].data();
            const double *uk = u + 3 * neighbour[i];
            f0 += B[0] * uk[0] + B[1] * uk[1] + B[2] * uk[2];
            f1 += B[3] * uk[0] + B[4] * uk[1] + B[5] * uk[2];
            f2 += B[6] * uk[0] + B[7] * uk[1] + B[8] * uk[2];
          }
        const double *D      = rows_inverse[j - row0].data();
        double       *uj     = u + 3 * j;
        double        opt[3] = {-(D[0] * f0 + D[1] * f1 + D[2] * f2),
                                -(D[3] * f0 + D[4] * f1 + D[5] * f2),
                                -(D[6] * f0 + D[7] * f1 + D[8] * f2)};
        double        wj     = w;
        if (constrained && model.constraint_of_point[j] >= 0)
          {
            model.constrained_update(
              j, opt, u, load, prescribed, stop_threshold, sweeps, queued);
            // The constrained minimiser whole: a relaxed step past it could
            // pass through the constraint.
            wj = 1.;
          }
        const double v[3] = {uj[0] + wj * (opt[0] - uj[0]),
                             uj[1] + wj * (opt[1] - uj[1]),
                             uj[2] + wj * (opt[2] - uj[2])};
        const double step = std::sqrt((v[0] - uj[0]) * (v[0] - uj[0]) +
                                      (v[1] - uj[1]) * (v[1] - uj[1]) +
                                      (v[2] - uj[2]) * (v[2] - uj[2]));
        if (!(step <= divergence_bound))
          {
            tally.failure = step;
            return false;
          }
        if (gauss_seidel)
          uj[0] = v[0], uj[1] = v[1], uj[2] = v[2];
        else
          jacobi_values[j] = {{v[0], v[1], v[2]}};

        // Paper, Sec. 2.3.3: the gradient over the point's last W updates, of
        // the change eq. 12 asks for (the step divided by the factor): a damped
        // update (factor below 1) would otherwise stop at once far from the
        // answer (factor 0.01), and an over-relaxed one would meet a
        // threshold that means less than the paper's (Table 1).
        const double change = step / wj;
        double      &slot =
          steps[static_cast<std::size_t>(j) * W + n_updates[j] % W];
        step_sum[j] += change - slot;
        slot               = change;
        tally.largest_step = std::max(tally.largest_step, step);
        ++n_updates[j];
        const bool stopped =
          n_updates[j] >= W && step_sum[j] / W < stop_threshold;
        tally.all_stopped &= stopped;

        if (!use_active_set)
          return true;
        if (!stopped)
          sweeps.queue(j, queued);
        if (step > stop_threshold)
          sweeps.queue_neighbours(j, queued);
        return true;
      }

      /// Jacobi order: the sweep's values at once.
      void
      finish_sweep(const std::vector<unsigned int> &points)
      {
        if (!gauss_seidel)
          for (const unsigned int j : points)
            for (unsigned int c = 0; c < 3; ++c)
              u[3 * j + c] = jacobi_values[j][c];
      }

      std::string
      too_many_sweeps(const PointSweeps               &sweeps,
                      const std::vector<unsigned int> &points) const;

      SweepDecision
      after_sweep(const PointSweeps &sweeps,
                  const SweepTally  &tally,
                  const bool         stop_proposed);

      /// The largest gradient of a point this rank updates (mm per sweep).
      double
      largest_gradient() const;

      /// Is a stop that the paper's criterion proposes checked?
      const bool        verify;
      StopDistanceCheck stop_check;

    private:
      /// A row of the precision history. Collective.
      void
      record_history(const PointSweeps &sweeps);

      const MassTensor     &model;
      PointSweeps          &sweeps;
      const Vector<double> &prescribed;
      Vector<double>       &displacement;
      const Vector<double> &converged;
      double *const         u;
      // This rank's rows, read in the local update from locals.
      const unsigned int *const row_start;
      const unsigned int *const neighbour;
      const Block *const        rows_coupling;
      const Block *const        rows_inverse;
      const std::size_t         entry0;
      const unsigned int        row0;
      const bool                gauss_seidel, use_active_set, constrained;
      const unsigned int        W;
      const double              w;
      /// No update of a converging scheme moves a point by more than the
      /// largest prescribed motion times a generous factor.
      const double divergence_bound;
      // Per point: its last W step lengths (a ring), their sum, its count.
      std::vector<double>                steps;
      std::vector<double>                step_sum;
      std::vector<unsigned int>          n_updates;
      std::vector<std::array<double, 3>> jacobi_values;
      std::ofstream                      history;
    };

    MassTensor::LocalUpdates::LocalUpdates(const MassTensor     &model,
                                           PointSweeps          &sweeps,
                                           const Vector<double> &prescribed,
                                           Vector<double>       &displacement,
                                           const Vector<double> &converged)
        : PointLocalUpdates(*model.scene,
                            model.stop_gradient_threshold > 0. ?
                              model.stop_gradient_threshold :
                              model.convergence_tolerance)
        , verify(model.stop_distance > 0. &&
                 model.stop_gradient_threshold > 0. &&
                 std::find(model.mesh->is_free.begin(),
                           model.mesh->is_free.end(),
                           true) != model.mesh->is_free.end())
        , stop_check(model.stop_distance,
                     model.gradient_window,
                     model.convergence_tolerance)
        , model(model)
        , sweeps(sweeps)
        , prescribed(prescribed)
        , displacement(displacement)
        , converged(converged)
        , u(displacement.begin())
        , row_start(model.mesh->row_start.data())
        , neighbour(model.mesh->neighbour.data())
        , rows_coupling(model.coupling.data())
        , rows_inverse(model.diagonal_inverse.data())
        , entry0(model.first_entry)
        , row0(model.first_row)
        , gauss_seidel(model.gauss_seidel)
        , use_active_set(model.use_active_set)
        , constrained(!model.constraint_of_point.empty())
        , W(model.gradient_window)
        , w(model.relaxation_factor())
        , divergence_bound(1e3 * (prescribed.linfty_norm() + 1.))
        , steps(static_cast<std::size_t>(model.mesh->n_points()) * W, 0.)
        , step_sum(model.mesh->n_points(), 0.)
        , n_updates(model.mesh->n_points(), 0)
    {
      if (!gauss_seidel)
        jacobi_values.resize(model.mesh->n_points());
      // On several MPI ranks rank 0 writes, and the ranks that share the
      // sweeps all learn whether it could (each throws, or none).
      const std::string &file = model.precision_history_file;
      if (file.empty())
        return;
      const bool first = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
      if (first)
        history.open(file);
      bool opened = history.is_open() || !first;
      if (model.exchange)
        opened = Utilities::MPI::min(int(opened), model.communicator) == 1;
      if (!opened)
        throw Error("mass tensor: cannot write 'Precision history file' '" +
                    file + "'.");
      if (history.is_open())
        history << "sweep,precision_max,precision_mean,max_gradient,"
                   "active_points\n"
                << std::setprecision(6);
    }

    std::string
    MassTensor::LocalUpdates::too_many_sweeps(
      const PointSweeps               &sweeps,
      const std::vector<unsigned int> &points) const
    {
      double g = 0.;
      for (const unsigned int j : points)
        g = std::max(g, step_sum[j] / W);
      g = sweeps.max(g);
      std::ostringstream m;
      m << std::setprecision(3) << "mass tensor: " << model.max_sweeps
        << " sweeps were not enough; " << sweeps.sum(points.size())
        << " points are still active, largest gradient " << g
        << " mm per sweep (threshold " << stop_threshold;
      if (stop_threshold < model.stop_gradient_threshold)
        m << ", lowered from " << model.stop_gradient_threshold
          << " by the stop check";
      m << ").";
      return m.str();
    }

    SweepDecision
    MassTensor::LocalUpdates::after_sweep(const PointSweeps &sweeps,
                                          const SweepTally  &tally,
                                          const bool         stop_proposed)
    {
      if (tally.failure > 0.)
        {
          std::ostringstream m;
          m << std::setprecision(3) << "mass tensor ("
            << (gauss_seidel ? "gauss-seidel" : "jacobi")
            << "): the local updates diverge (";
          if (std::isinf(tally.failure))
            m << "an update became infinite or NaN";
          else
            m << "a point moved by " << tally.failure << " mm";
          m << " in sweep " << sweeps.n_sweeps()
            << "). Jacobi order does not converge for every mesh and "
               "Poisson's ratio; use 'Ordering = gauss-seidel' or a "
               "'Relaxation factor' below 1.";
          throw Error(m.str());
        }
      if (history.is_open() ||
          (model.exchange && !model.precision_history_file.empty()))
        record_history(sweeps);
      stop_check.record(tally.largest_step);
      // The paper's criterion (Sec. 2.3.3) proposes the stop.
      if (!stop_proposed)
        return SweepDecision::go_on;
      if (!verify || stop_check.accept(stop_threshold))
        return SweepDecision::stop;
      return SweepDecision::sweep_every_point;
    }

    double
    MassTensor::LocalUpdates::largest_gradient() const
    {
      double gradient = 0.;
      for (unsigned int j = 0; j < n_updates.size(); ++j)
        if (sweeps.updates(j) && n_updates[j] > 0)
          gradient =
            std::max(gradient, step_sum[j] / std::min(n_updates[j], W));
      return gradient;
    }

    void
    MassTensor::LocalUpdates::record_history(const PointSweeps &sweeps)
    {
      // The points active after the sweep.
      const auto     n_active = sweeps.sum(sweeps.points().size());
      const double   gradient = sweeps.max(largest_gradient());
      Vector<double> whole;
      if (model.exchange)
        {
          whole = displacement;
          model.exchange->gather(whole.begin());
        }
      const auto distance = Displacement::free_vertex_difference(
        *model.scene, model.exchange ? whole : displacement, converged);
      if (!history.is_open())
        return;
      history << sweeps.n_sweeps() << ',' << distance.max << ','
              << distance.mean << ',' << gradient << ',' << n_active << '\n';
    }

    void
    MassTensor::do_solve(const Vector<double> &prescribed,
                         Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("MassTensor::setup() first."));
      const unsigned int n = mesh->n_points();
      displacement.reinit(3 * n);
      for (unsigned int j = 0; j < n; ++j)
        if (!mesh->is_free[j])
          for (unsigned int c = 0; c < 3; ++c)
            displacement[3 * j + c] = prescribed[3 * j + c];

      // The points this rank updates: the free ones, on several MPI ranks
      // those it owns (PointSweeps).
      PointSweeps::Settings settings;
      settings.values       = displacement.begin();
      settings.max_sweeps   = max_sweeps;
      settings.active_set   = use_active_set;
      settings.gauss_seidel = gauss_seidel;
      PointSweeps sweeps(*mesh, *colouring, exchange.get(), settings, progress);
      queue_first_sweep(sweeps, displacement.begin());

      // The precision needs the converged answer (the study during the
      // sweeps, the report at the end). Linear FEM's answer to the plan,
      // when the run has it, is that answer already (to its solver's
      // tolerance): not solved again.
      Vector<double> converged;
      const bool     reuse = converged_answer != nullptr &&
                         converged_answer->size() == prescribed.size();
      if (reuse)
        converged = *converged_answer;
      else if (report_precision || !precision_history_file.empty())
        solve_converged(prescribed, converged);

      LocalUpdates updates(*this, sweeps, prescribed, displacement, converged);
      Timer        sweep_timer;
      auto         sweeps_phase = phase("sweeps");
      sweeps.run(updates);
      const double sweep_time = sweep_timer.wall_time();
      sweeps_phase.stop();
      if (exchange)
        {
          const auto timed = phase("gather");
          exchange->gather(displacement.begin());
        }
      report_solve(updates,
                   sweeps,
                   sweep_time,
                   prescribed,
                   displacement,
                   converged,
                   reuse);
    }

    void
    MassTensor::queue_first_sweep(PointSweeps        &sweeps,
                                  const double *const u) const
    {
      const auto &row_start = mesh->row_start;
      const auto &neighbour = mesh->neighbour;
      const auto &is_free   = mesh->is_free;
      for (unsigned int j = 0; j < mesh->n_points(); ++j)
        if (sweeps.updates(j))
          {
            bool touched =
              !use_active_set || scene->has_body_force() ||
              (!constraint_of_point.empty() && constraint_of_point[j] >= 0);
            for (unsigned int i = row_start[j];
                 i < row_start[j + 1] && !touched;
                 ++i)
              {
                const unsigned int k = neighbour[i];
                touched =
                  !is_free[k] &&
                  (u[3 * k] != 0. || u[3 * k + 1] != 0. || u[3 * k + 2] != 0.);
              }
            if (touched)
              sweeps.queue(j);
          }
    }

    double
    MassTensor::relative_residual(const Vector<double> &prescribed,
                                  const double *const   u) const
    {
      const auto         &row_start = mesh->row_start;
      const auto         &neighbour = mesh->neighbour;
      const auto         &is_free   = mesh->is_free;
      const double *const load =
        scene->has_body_force() ? scene->effects.body_force.begin() : nullptr;
      const std::vector<char> mine = points_to_update(*mesh, exchange.get());
      double                  residual = 0., initial = 0.;
      for (unsigned int j = 0; j < mesh->n_points(); ++j)
        if (mine[j])
          {
            double r[3] = {0., 0., 0.}, f[3] = {0., 0., 0.};
            for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
              {
                const double *B  = coupling_of(i);
                const double *uk = u + 3 * neighbour[i];
                for (unsigned int a = 0; a < 3; ++a)
                  {
                    const double t = B[3 * a] * uk[0] + B[3 * a + 1] * uk[1] +
                                     B[3 * a + 2] * uk[2];
                    r[a] += t;
                    if (!is_free[neighbour[i]])
                      f[a] += t;
                  }
              }
            if (load != nullptr)
              for (unsigned int a = 0; a < 3; ++a)
                {
                  r[a] -= load[3 * j + a];
                  f[a] -= load[3 * j + a];
                }
            const double *B  = diagonal[j - first_row].data();
            const double *uj = u + 3 * j;
            for (unsigned int a = 0; a < 3; ++a)
              r[a] +=
                B[3 * a] * uj[0] + B[3 * a + 1] * uj[1] + B[3 * a + 2] * uj[2];
            // A constraint in contact takes up the force along its normal.
            if (!constraint_of_point.empty() && constraint_of_point[j] >= 0)
              {
                const PointConstraint &c =
                  point_constraints[constraint_of_point[j]];
                double gap = 0., rn = 0.;
                for (unsigned int a = 0; a < 3; ++a)
                  {
                    gap += c.n[a] * (c.a == c.b ?
                                       u[3 * j + a] - prescribed[3 * j + a] :
                                       u[3 * c.a + a] - u[3 * c.b + a]);
                    rn += c.n[a] * r[a];
                  }
                if (!c.unilateral ||
                    std::abs(gap) <= 1e-9 * (prescribed.linfty_norm() + 1e-300))
                  for (unsigned int a = 0; a < 3; ++a)
                    r[a] -= rn * c.n[a];
              }
            for (unsigned int a = 0; a < 3; ++a)
              {
                residual += r[a] * r[a];
                initial += f[a] * f[a];
              }
          }
      if (exchange)
        {
          std::array<double, 2> sums = {{residual, initial}};
          Utilities::MPI::sum(ArrayView<const double>(sums),
                              communicator,
                              ArrayView<double>(sums));
          residual = sums[0];
          initial  = sums[1];
        }
      return initial > 0. ? std::sqrt(residual / initial) : 0.;
    }

    void
    MassTensor::report_solve(const LocalUpdates   &updates,
                             const PointSweeps    &sweeps,
                             const double          sweep_time,
                             const Vector<double> &prescribed,
                             const Vector<double> &displacement,
                             const Vector<double> &converged,
                             const bool            reused_answer)
    {
      const double residual =
        relative_residual(prescribed, displacement.begin());
      const unsigned long long own_updates   = sweeps.n_point_updates();
      const unsigned long long point_updates = sweeps.sum(own_updates);

      last_report               = Report();
      last_report.sweeps        = sweeps.n_sweeps();
      last_report.point_updates = point_updates;
      last_report.max_gradient  = sweeps.max(updates.largest_gradient());

      set_iterations(sweeps.n_sweeps());
      set_residual(residual);
      add_detail("point updates", point_updates);
      // A rank's own: its sweeps' time over the updates it made.
      add_detail("ns per update",
                 own_updates ? 1e9 * sweep_time / own_updates : 0.,
                 "",
                 true);
      for (const auto &figure : sweeps.rank_figures())
        add_detail(figure.first, figure.second);
      add_detail("max gradient", last_report.max_gradient, "mm/sweep");
      if (updates.verify)
        {
          const StopDistanceCheck &check = updates.stop_check;
          add_detail("stop checks", check.n_checks());
          if (check.unchecked())
            warn("mass tensor: the stop could not be checked (the largest "
                 "change per sweep did not shrink, or the threshold reached "
                 "the convergence tolerance); its distance to the answer is "
                 "not known.");
          add_detail("contraction rate", check.rate());
          add_detail("estimated distance", check.distance_left(), "mm");
          add_detail("final threshold", updates.threshold(), "mm/sweep");
        }
      if (report_precision)
        {
          const auto distance =
            Displacement::free_vertex_difference(*scene,
                                                 displacement,
                                                 converged);
          last_report.precision_max  = distance.max;
          last_report.precision_mean = distance.mean;
          add_detail("precision against",
                     reused_answer ? "linear fem's answer" :
                                     "its own direct solve");
          add_detail("precision max", distance.max, "mm");
          add_detail("precision mean", distance.mean, "mm");
        }
    }

    unsigned int
    MassTensor::n_points() const
    {
      return mesh ? mesh->n_points() : 0;
    }

    Tensor<2, 3>
    MassTensor::tensor(const unsigned int j, const unsigned int k) const
    {
      AssertThrow(holds_tensors(j),
                  ExcMessage("Point " + std::to_string(j) +
                             "'s tensors are another MPI rank's."));
      const Block *block = nullptr;
      if (j == k)
        block = &diagonal[j - first_row];
      else
        {
          const auto &neighbour = mesh->neighbour;
          const auto  begin     = neighbour.begin() + mesh->row_start[j];
          const auto  end       = neighbour.begin() + mesh->row_start[j + 1];
          const auto  it        = std::lower_bound(begin, end, k);
          if (it != end && *it == k)
            block = &coupling[(it - neighbour.begin()) - first_entry];
        }
      Tensor<2, 3> K;
      if (block != nullptr)
        for (unsigned int r = 0; r < 3; ++r)
          for (unsigned int s = 0; s < 3; ++s)
            K[r][s] = (*block)[3 * r + s];
      return K;
    }

    const MassTensor::Report &
    MassTensor::report() const
    {
      return last_report;
    }

    SOFTFACE_REGISTER_MODEL(MassTensor,
                            "mass tensor",
                            "Cotin's mass tensor model with the static local "
                            "update (Mollemans et al. 2007, Sec. 2.3.2) and "
                            "local dynamic stop criterion with active set "
                            "(Sec. 2.3.3).")
  } // namespace Models
} // namespace softface

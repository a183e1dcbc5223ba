// The mass spring model (models; Mollemans et al. 2007, Sec. 2.2): a spring per
// edge with Gelder's constants, nonlinear in the positions, and its static
// equilibrium by local steepest descent with the paper's dynamic cut-out.

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/tetrahedron.h>
#include <softface/models/block_colouring.h>
#include <softface/models/mass_spring.h>
#include <softface/models/point_constraints.h>
#include <softface/models/point_exchange.h>
#include <softface/models/point_sweeps.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace softface
{
  namespace Models
  {
    MassSpring::MassSpring() = default;

    MassSpring::~MassSpring() = default;

    void
    MassSpring::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry(
        "Stop threshold",
        "0.001",
        Patterns::Double(0.),
        "A point moves while its step |F| / sum(k) of its "
        "springs exceeds this (mm): the force threshold "
        "of the dynamic cut-out (Mollemans et al. 2007, Sec. 2.2), "
        "independent of E.");
      prm.declare_entry("Maximum step fraction",
                        "0.25",
                        Patterns::Double(0., 0.5),
                        "A point never moves by more than this fraction of its "
                        "shortest spring in one update, so that no spring "
                        "flips.");
      prm.declare_entry(
        "Prevent inversion",
        "false",
        Patterns::Bool(),
        "true halves a step that would turn a tetrahedron "
        "inside out (up to 8 times, else skips it) and makes "
        "any inversion an error. false is the model of Mollemans et al. 2007: "
        "springs may flip over where the equilibrium of the "
        "springs asks for it; the inverted tetrahedra are "
        "counted and reported with a warning.");
      prm.declare_entry("Warm start",
                        "true",
                        Patterns::Bool(),
                        "A solve after the first of a setup (the next plan of "
                        "a scene with several) starts from the previous "
                        "answer, its join points carried in load steps from "
                        "the previous plan's positions to this one's. false: "
                        "every solve starts at rest.");
      prm.declare_entry("Maximum sweeps",
                        "200000",
                        Patterns::Integer(1),
                        "A solve that needs more sweeps stops with an error "
                        "stating the largest step still pending.");
    }

    void
    MassSpring::parse_parameters(ParameterHandler &prm)
    {
      stop_threshold    = prm.get_double("Stop threshold");
      max_step_fraction = prm.get_double("Maximum step fraction");
      max_sweeps        = prm.get_integer("Maximum sweeps");
      prevent_inversion = prm.get_bool("Prevent inversion");
      warm_start        = prm.get_bool("Warm start");
      // Zero would ask for infinitely many load steps.
      if (!(max_step_fraction > 0.))
        throw Error("mass spring: 'Maximum step fraction' must be positive "
                    "(got " +
                    prm.get("Maximum step fraction") + ").");
    }

    void
    MassSpring::set_stop_threshold(const double threshold_mm)
    {
      stop_threshold = threshold_mm;
    }

    void
    MassSpring::set_prevent_inversion(const bool prevent)
    {
      prevent_inversion = prevent;
    }

    bool
    MassSpring::runs_without_scene_cells() const
    {
      return true;
    }

    unsigned int
    MassSpring::honoured_effects() const
    {
      return SceneEffects::cell_materials | SceneEffects::body_forces |
             SceneEffects::free_vertex_constraints;
    }

    void
    MassSpring::do_setup(const Scene &scene_in)
    {
      scene = &scene_in;
      last_position.clear();
      auto timed = phase("springs");
      mesh = std::make_unique<PointMesh>(*scene, "mass spring", communicator);
      const unsigned int n         = mesh->n_points();
      const auto        &row_start = mesh->row_start;
      const auto        &neighbour = mesh->neighbour;

      // The paper's eq. 5: every edge once, with the volume of the tetrahedra
      // that share it (summed at the edge's position (j, k), j < k). With
      // heterogeneous tissue each cell's volume is weighted by its modulus
      // relative to Scene::material's (Gelder's formula per cell).
      const double        E = scene->material.youngs_modulus();
      std::vector<double> weight;
      for (unsigned int t = 0; t < scene->n_tissues(); ++t)
        weight.push_back(scene->tissue(t).youngs_modulus() / E);
      std::vector<double> edge_volume(neighbour.size(), 0.);
      for (unsigned int c = 0; c < mesh->tetrahedra.size(); ++c)
        {
          const auto  &p      = mesh->tetrahedra[c];
          const double volume = weight[mesh->tissue[c]] *
                                Tetrahedron::signed_volume(mesh->vertices(c));
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int b = a + 1; b < 4; ++b)
              edge_volume[mesh->edge_index(std::min(p[a], p[b]),
                                           std::max(p[a], p[b]))] += volume;
        }
      spring_list.clear();
      spring_of.assign(neighbour.size(), 0);
      total_stiffness.assign(n, 0.);
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
          {
            const unsigned int k = neighbour[i];
            if (k < j)
              {
                spring_of[i] = spring_of[mesh->edge_index(k, j)];
                continue;
              }
            const double L0 = mesh->position[j].distance(mesh->position[k]);
            spring_of[i]    = spring_list.size();
            spring_list.push_back({j, k, L0, E * edge_volume[i] / (L0 * L0)});
          }
      for (const Spring &spring : spring_list)
        {
          total_stiffness[spring.a] += spring.stiffness;
          total_stiffness[spring.b] += spring.stiffness;
        }

      add_detail("springs", spring_list.size());
      timed.stop();

      make_point_constraints(*scene, n, point_constraints, constraint_of_point);

      // A constrained update moves its partner too, further than a block's
      // colour keeps apart: such scenes sweep in plain order on one thread.
      colouring = scene->has_vertex_constraints() ?
                    std::make_unique<BlockColouring>(mesh->n_points()) :
                    std::make_unique<BlockColouring>(mesh->n_points(),
                                                     mesh->row_start,
                                                     mesh->neighbour);
      // On several MPI ranks each moves the points of its blocks.
      exchange = point_exchange(*scene, *colouring, *mesh);
    }

    /**
     * The mass spring model's part of its sweeps (PointSweeps): a point's
     * local steepest-descent step under its springs (the paper's eq. 4) and its
     * constraint, halved where it would invert a tetrahedron; a load step
     * ends where the dynamic cut-out leaves no point to move.
     */
    class MassSpring::LocalUpdates : public PointLocalUpdates
    {
    public:
      LocalUpdates(const MassSpring      &model,
                   PointSweeps           &sweeps,
                   std::vector<Point<3>> &x,
                   const Vector<double>  &prescribed,
                   const bool             warm);

      // Inlined into the sweep's loop over a block's points (GCC would
      // call it once per point).
      DEAL_II_ALWAYS_INLINE bool
      update(const unsigned int         j,
             SweepTally                &tally,
             std::vector<unsigned int> &queued)
      {
        Tensor<1, 3>       step = free_step(j), step_other;
        const unsigned int partner =
          (constrained && model.constraint_of_point[j] >= 0) ?
            constrain(j, step, step_other) :
            numbers::invalid_unsigned_int;
        const bool   paired = partner != numbers::invalid_unsigned_int;
        const double size =
          std::max(step.norm(), paired ? step_other.norm() : 0.);
        if (!(size > stop_threshold))
          {
            if (!std::isfinite(size))
              {
                tally.failure = std::numeric_limits<double>::infinity();
                return false;
              }
            return true;
          }
        // Springs alone do not keep a tetrahedron from turning inside out
        // (paper, Sec. 2.2, disadvantage 1): a step that would invert one is
        // halved until it does not, or not taken.
        const Point<3> old      = x[j];
        unsigned int   halvings = 0;
        for (; halvings < 8 && prevent_inversion; ++halvings, step *= 0.5)
          {
            x[j] = old + step;
            if (!inverts_a_tetrahedron(j))
              break;
          }
        if (!prevent_inversion)
          x[j] = old + step;
        else if (halvings == 8)
          {
            x[j] = old;
            ++tally.held_back;
            return true;
          }
        // A pair moves together (by as much of its step as j).
        if (paired)
          x[partner] +=
            (prevent_inversion ? std::pow(0.5, halvings) : 1.) * step_other;
        // Their own forces and their neighbours' have changed. A step lost
        // in rounding moved nothing (a stop threshold of 0): nothing to
        // wake, as a rank that reads j as a ghost sees (PointExchange).
        if (paired || x[j] != old)
          {
            sweeps.queue(j, queued);
            sweeps.queue_neighbours(j, queued);
          }
        if (paired)
          {
            sweeps.queue(partner, queued);
            sweeps.queue_neighbours(partner, queued);
          }
        return true;
      }

      std::string
      too_many_sweeps(const PointSweeps               &sweeps,
                      const std::vector<unsigned int> &points) const;

      SweepDecision
      after_sweep(const PointSweeps &sweeps,
                  const SweepTally  &tally,
                  const bool         stop_proposed) const;

      /// The force on point j (the paper's eq. 4) and its shortest spring.
      Tensor<1, 3>
      force(const unsigned int j, double &shortest) const
      {
        const auto  &row_start = model.mesh->row_start;
        const auto  &other_end = model.mesh->neighbour;
        Tensor<1, 3> F;
        if (load != nullptr)
          for (unsigned int c = 0; c < 3; ++c)
            F[c] = load[3 * j + c];
        shortest = std::numeric_limits<double>::max();
        for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
          {
            const Spring      &s      = model.spring_list[model.spring_of[i]];
            const Tensor<1, 3> d      = x[other_end[i]] - x[j];
            const double       length = d.norm();
            shortest                  = std::min(shortest, length);
            F += s.stiffness * (length - s.rest_length) / length * d;
          }
        return F;
      }

      /// The step a point's force asks for: F / sum k, never more than a
      /// fraction of its shortest spring (so no spring flips in one step).
      Tensor<1, 3>
      free_step(const unsigned int j) const
      {
        double       shortest;
        Tensor<1, 3> step = force(j, shortest) / model.total_stiffness[j];
        const double size = step.norm();
        if (size > model.max_step_fraction * shortest)
          step *= model.max_step_fraction * shortest / size;
        return step;
      }

      /**
       * Move @p step of point j onto its constraint: a sliding point stays
       * on the bone surface (orthogonal projection: the springs' stiffness
       * at a point is isotropic). A pair moves together (a block update of
       * both points): @p step_other is the partner's step, the two closing
       * their gap weighted by 1 / sum k if it would open below zero.
       * Returns the partner, or numbers::invalid_unsigned_int.
       */
      unsigned int
      constrain(const unsigned int j,
                Tensor<1, 3>      &step,
                Tensor<1, 3>      &step_other) const;

      /// Move the join points to @p load_step of @p n_load_steps of their
      /// motion, and queue the points that feel it.
      void
      start_load_step(const unsigned int load_step,
                      const unsigned int n_load_steps);

      /// The positions (points in the serial numbering).
      std::vector<Point<3>> &x;
      /// The join displacement the load steps start from (Warm start: the
      /// previous plan's), and the motion they add to it.
      Vector<double> start, motion;
      /// The join points that move (load_steps()).
      std::vector<unsigned int> moving_joins;

    private:
      /// Does a tetrahedron at point j turn inside out at x?
      bool
      inverts_a_tetrahedron(const unsigned int j) const;

      const MassSpring &model;
      PointSweeps      &sweeps;
      const bool        constrained, prevent_inversion;
      double            fraction  = 0.; ///< of the motion applied
      unsigned int      load_step = 0, n_load_steps = 0;
    };

    MassSpring::LocalUpdates::LocalUpdates(const MassSpring      &model,
                                           PointSweeps           &sweeps,
                                           std::vector<Point<3>> &x,
                                           const Vector<double>  &prescribed,
                                           const bool             warm)
        : PointLocalUpdates(*model.scene, model.stop_threshold)
        , x(x)
        , start(prescribed.size())
        , motion(prescribed)
        , model(model)
        , sweeps(sweeps)
        , constrained(!model.constraint_of_point.empty())
        , prevent_inversion(model.prevent_inversion)
    {
      if (warm)
        start = model.last_prescribed;
      motion -= start;
    }

    unsigned int
    MassSpring::LocalUpdates::constrain(const unsigned int j,
                                        Tensor<1, 3>      &step,
                                        Tensor<1, 3>      &step_other) const
    {
      const auto            &rest_position = model.mesh->position;
      const auto            &k             = model.total_stiffness;
      const PointConstraint &c =
        model.point_constraints[model.constraint_of_point[j]];
      if (c.a == c.b)
        {
          Tensor<1, 3> bone;
          for (unsigned int d = 0; d < 3; ++d)
            bone[d] = start[3 * j + d] + fraction * motion[3 * j + d];
          const double gap = c.n * (x[j] + step - rest_position[j] - bone);
          if (!c.unilateral || gap < 0.)
            step -= gap * c.n;
          return numbers::invalid_unsigned_int;
        }
      const unsigned int other = (j == c.a ? c.b : c.a);
      step_other               = free_step(other);
      Tensor<1, 3> &s_a        = (j == c.a ? step : step_other);
      Tensor<1, 3> &s_b        = (j == c.a ? step_other : step);
      const double  gap        = c.n * ((x[c.a] + s_a - rest_position[c.a]) -
                                (x[c.b] + s_b - rest_position[c.b]));
      if (!c.unilateral || gap < 0.)
        {
          const double lambda = -gap / (1. / k[c.a] + 1. / k[c.b]);
          s_a += lambda / k[c.a] * c.n;
          s_b -= lambda / k[c.b] * c.n;
        }
      return other;
    }

    bool
    MassSpring::LocalUpdates::inverts_a_tetrahedron(const unsigned int j) const
    {
      const PointMesh &mesh = *model.mesh;
      for (unsigned int t = mesh.tet_start[j]; t < mesh.tet_start[j + 1]; ++t)
        {
          const auto &v = mesh.tetrahedra[mesh.tets_of_point[t]];
          if (Tetrahedron::signed_volume(
                {{x[v[0]], x[v[1]], x[v[2]], x[v[3]]}}) <= 0.)
            return true;
        }
      return false;
    }

    void
    MassSpring::LocalUpdates::start_load_step(const unsigned int step,
                                              const unsigned int n_steps)
    {
      load_step    = step;
      n_load_steps = n_steps;
      fraction     = double(load_step) / n_load_steps;
      // A sliding point follows its bone surface.
      for (const auto &c : model.point_constraints)
        sweeps.queue(c.a), sweeps.queue(c.b);
      // The load is there from the start: every free point feels it.
      if (load_step == 1 && load != nullptr)
        for (unsigned int j = 0; j < x.size(); ++j)
          if (sweeps.updates(j))
            sweeps.queue(j);
      const auto &rest_position = model.mesh->position;
      const auto &row_start     = model.mesh->row_start;
      for (const unsigned int j : moving_joins)
        {
          for (unsigned int c = 0; c < 3; ++c)
            x[j][c] = rest_position[j][c] + start[3 * j + c] +
                      fraction * motion[3 * j + c];
          for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
            {
              const unsigned int k = model.mesh->neighbour[i];
              if (sweeps.updates(k))
                sweeps.queue(k);
            }
        }
    }

    std::string
    MassSpring::LocalUpdates::too_many_sweeps(
      const PointSweeps               &sweeps,
      const std::vector<unsigned int> &points) const
    {
      double pending = 0., shortest;
      for (const unsigned int j : points)
        pending =
          std::max(pending,
                   force(j, shortest).norm() / model.total_stiffness[j]);
      pending = sweeps.max(pending);
      std::ostringstream m;
      m << "mass spring: " << model.max_sweeps
        << " sweeps were not enough (load step " << load_step << " of "
        << n_load_steps << "); " << sweeps.sum(points.size())
        << " points are still active, largest pending step " << pending
        << " mm (threshold " << stop_threshold << " mm).";
      return m.str();
    }

    SweepDecision
    MassSpring::LocalUpdates::after_sweep(const PointSweeps &sweeps,
                                          const SweepTally  &tally,
                                          const bool stop_proposed) const
    {
      if (tally.failure > 0.)
        throw Error("mass spring: the force on a point became infinite or "
                    "NaN (a spring of zero length) in sweep " +
                    std::to_string(sweeps.n_sweeps()) + ".");
      // The dynamic cut-out: the load step ends where no rank has a point
      // to move.
      return stop_proposed ? SweepDecision::stop : SweepDecision::go_on;
    }

    void
    MassSpring::do_solve(const Vector<double> &prescribed,
                         Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("MassSpring::setup() first."));
      static_assert(sizeof(Point<3>) == 3 * sizeof(double),
                    "the exchange reads positions as 3 doubles per point");
      // Warm start: from the previous plan's answer; the load steps carry
      // the join points from that plan's positions ('start') to this one's.
      const bool warm = warm_start && last_position.size() == mesh->n_points();
      std::vector<Point<3>> x(warm ? last_position : mesh->position);
      // The points this rank moves: the free ones, on several MPI ranks
      // those it owns (PointSweeps).
      PointSweeps::Settings settings;
      settings.values             = &x[0][0];
      settings.max_sweeps         = max_sweeps;
      settings.wake_on_any_change = true;
      PointSweeps sweeps(*mesh, *colouring, exchange.get(), settings, progress);
      LocalUpdates       updates(*this, sweeps, x, prescribed, warm);
      const unsigned int n_load_steps = load_steps(updates);

      // The force at the start, the join points moved all at once.
      double initial = 0.;
      for (const unsigned int j : updates.moving_joins)
        for (unsigned int c = 0; c < 3; ++c)
          x[j][c] = mesh->position[j][c] + prescribed[3 * j + c];
      for (unsigned int j = 0; j < mesh->n_points(); ++j)
        if (mesh->is_free[j])
          {
            double shortest;
            initial += updates.force(j, shortest).norm_square();
          }

      unsigned int rebalances = 0;
      for (unsigned int load_step = 1; load_step <= n_load_steps; ++load_step)
        {
          updates.start_load_step(load_step, n_load_steps);
          sweeps.run(updates,
                     " (load step " + std::to_string(load_step) + " of " +
                       std::to_string(n_load_steps) + ")");
          if (exchange && load_step < n_load_steps)
            rebalances += rebalance(sweeps, x);
        }

      if (exchange)
        {
          const auto timed = phase("gather");
          exchange->gather(&x[0][0]);
        }
      displacement.reinit(3 * mesh->n_points());
      for (unsigned int j = 0; j < mesh->n_points(); ++j)
        for (unsigned int c = 0; c < 3; ++c)
          displacement[3 * j + c] = x[j][c] - mesh->position[j][c];
      report_solve(updates, sweeps, initial, n_load_steps, rebalances, warm);
      // The next plan starts here.
      last_position   = x;
      last_prescribed = prescribed;
    }

    unsigned int
    MassSpring::load_steps(LocalUpdates &updates) const
    {
      // Moving the join points all at once can push a bone point past its
      // free neighbours, flipping springs before any free point has moved.
      // The motion is applied in load steps, each shorter than the step
      // bound of the shortest spring at a moving join point.
      const auto &row_start      = mesh->row_start;
      const auto &motion         = updates.motion;
      double      largest_motion = 0., shortest_at_join = 1e300;
      updates.moving_joins.clear();
      for (unsigned int j = 0; j < mesh->n_points(); ++j)
        if (!mesh->is_free[j])
          {
            const double length =
              std::sqrt(motion[3 * j] * motion[3 * j] +
                        motion[3 * j + 1] * motion[3 * j + 1] +
                        motion[3 * j + 2] * motion[3 * j + 2]);
            if (length == 0.)
              continue;
            updates.moving_joins.push_back(j);
            largest_motion = std::max(largest_motion, length);
            for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
              if (mesh->is_free[mesh->neighbour[i]])
                shortest_at_join =
                  std::min(shortest_at_join,
                           spring_list[spring_of[i]].rest_length);
          }
      // A bone surface that sliding points follow moves them like join
      // points.
      bool surface_moves = false;
      for (const auto &c : point_constraints)
        if (c.a == c.b)
          {
            const double length =
              std::sqrt(motion[3 * c.a] * motion[3 * c.a] +
                        motion[3 * c.a + 1] * motion[3 * c.a + 1] +
                        motion[3 * c.a + 2] * motion[3 * c.a + 2]);
            if (length == 0.)
              continue;
            surface_moves  = true;
            largest_motion = std::max(largest_motion, length);
            for (unsigned int i = row_start[c.a]; i < row_start[c.a + 1]; ++i)
              shortest_at_join =
                std::min(shortest_at_join,
                         spring_list[spring_of[i]].rest_length);
          }
      // A load alone (no bone moves) still needs one step.
      const double steps_needed =
        updates.moving_joins.empty() && !surface_moves ?
          (scene->has_body_force() ? 1 : 0) :
          std::max(1.,
                   std::ceil(largest_motion /
                             (max_step_fraction * shortest_at_join)));
      // A motion far larger than the mesh (or a tiny step fraction) would
      // take more load steps than any run can: say so rather than overflow.
      constexpr double max_load_steps = 1e6;
      if (!(steps_needed <= max_load_steps))
        {
          std::ostringstream m;
          m << std::setprecision(3) << "mass spring: the largest join motion ("
            << largest_motion << " mm) in steps of 'Maximum step fraction' ("
            << max_step_fraction << ") times the shortest spring at a join "
            << "point (" << shortest_at_join << " mm) needs " << steps_needed
            << " load steps, more than " << max_load_steps << ".";
          throw Error(m.str());
        }
      return steps_needed;
    }

    bool
    MassSpring::rebalance(PointSweeps &sweeps, std::vector<Point<3>> &x)
    {
      // On several ranks, after a load step (no point is pending on any
      // rank): the blocks shared again by that step's updates. The cut-out
      // works where the motion is, which the first partition, by free
      // points, need not split evenly (a colour waits for its busiest
      // rank), and that region changes from step to step (on the generated
      // cube the ranks' shares of the updates go from 51:49 in the first
      // step to 2:1 in the tenth); the last step's work is the best guess at
      // the next's. Any range of blocks makes the serial updates
      // (PointExchange): the answer does not change. PointExchange adds each
      // block's free points, so that blocks the step did not reach still
      // spread.
      const auto           timed      = phase("rebalance");
      std::vector<double> &block_work = sweeps.block_updates();
      Utilities::MPI::sum(block_work, communicator, block_work);
      // The same on every rank (block_work is): unchanged ranges keep the
      // exchange.
      bool moved = false;
      if (PointExchange::block_ranges(*colouring,
                                      *mesh,
                                      Utilities::MPI::n_mpi_processes(
                                        communicator),
                                      block_work) != exchange->ranges())
        {
          // Every point's position on every rank: a new ghost's too.
          exchange->gather(&x[0][0]);
          exchange = std::make_unique<PointExchange>(*colouring,
                                                     *mesh,
                                                     communicator,
                                                     block_work);
          sweeps.use_exchange(exchange.get());
          moved = true;
        }
      std::fill(block_work.begin(), block_work.end(), 0.);
      return moved;
    }

    void
    MassSpring::report_solve(const LocalUpdates &updates,
                             const PointSweeps  &sweeps,
                             const double        initial,
                             const unsigned int  n_load_steps,
                             const unsigned int  rebalances,
                             const bool          warm)
    {
      const std::vector<Point<3>> &x = updates.x;
      last_report                    = Report();
      last_report.sweeps             = sweeps.n_sweeps();
      last_report.load_steps         = n_load_steps;
      last_report.point_updates      = sweeps.sum(sweeps.n_point_updates());
      last_report.blocked_updates    = sweeps.sum(sweeps.n_held_back());
      last_report.rebalances         = rebalances;
      double residual                = 0.;
      for (unsigned int j = 0; j < x.size(); ++j)
        if (sweeps.updates(j))
          {
            double       shortest;
            Tensor<1, 3> F = updates.force(j, shortest);
            // A constrained point: the step it would take under its
            // constraint (what the constraint takes up is no residual).
            if (!constraint_of_point.empty() && constraint_of_point[j] >= 0)
              {
                Tensor<1, 3> step = updates.free_step(j), step_other;
                if (updates.constrain(j, step, step_other) !=
                    numbers::invalid_unsigned_int)
                  step = step.norm() > step_other.norm() ? step : step_other;
                F = step * total_stiffness[j];
              }
            const double f = F.norm();
            last_report.max_step =
              std::max(last_report.max_step, f / total_stiffness[j]);
            residual += f * f;
          }
      if (exchange)
        {
          residual             = Utilities::MPI::sum(residual, communicator);
          last_report.max_step = sweeps.max(last_report.max_step);
          for (const auto &figure : sweeps.rank_figures())
            add_detail(figure.first, figure.second);
          // The ranges and ghosts above are the last load step's; the next
          // plan starts from them.
          add_detail("load steps that moved blocks between ranks", rebalances);
        }
      // A tetrahedron of join points only (across a kerf) moves as the bones
      // move it: when the planning inverts it, the springs have no say.
      for (const auto &t : mesh->tetrahedra)
        if (mesh->is_free[t[0]] || mesh->is_free[t[1]] || mesh->is_free[t[2]] ||
            mesh->is_free[t[3]])
          last_report.inverted_tetrahedra +=
            (Tetrahedron::signed_volume(
               {{x[t[0]], x[t[1]], x[t[2]], x[t[3]]}}) <= 0.);

      set_iterations(sweeps.n_sweeps());
      set_residual(initial > 0. ? std::sqrt(residual / initial) : 0.);
      if (warm)
        add_detail("warm start", "from the previous plan");
      add_detail("load steps", n_load_steps);
      add_detail("point updates", last_report.point_updates);
      add_detail("largest pending step", last_report.max_step, "mm");
      add_detail("blocked updates", last_report.blocked_updates);
      add_detail("inverted tetrahedra", last_report.inverted_tetrahedra);
      check_equilibrium(sweeps.n_sweeps(), n_load_steps);
    }

    void
    MassSpring::check_equilibrium(const unsigned int sweeps,
                                  const unsigned int n_load_steps)
    {
      const Report &r = last_report;
      if (!prevent_inversion && r.inverted_tetrahedra > 0 &&
          r.max_step <= stop_threshold)
        warn("reached equilibrium with " +
             std::to_string(r.inverted_tetrahedra) +
             " inverted tetrahedra (springs flipped over, Mollemans et al. "
             "2007, Sec. 2.2); the "
             "answer is not physical there.");
      else if (r.inverted_tetrahedra > 0 || r.max_step > stop_threshold)
        {
          std::ostringstream m;
          m << "mass spring: no equilibrium reached after " << sweeps
            << " sweeps in " << n_load_steps << " load steps: largest pending "
            << "step " << r.max_step << " mm (threshold " << stop_threshold
            << " mm), " << r.inverted_tetrahedra << " inverted tetrahedra, "
            << r.blocked_updates
            << " updates held back because they would have inverted a "
               "tetrahedron. Springs alone cannot keep tetrahedra from "
               "collapsing under this motion (Mollemans et al. 2007, Sec. "
               "2.2); refine the mesh or "
               "use another model.";
          throw Error(m.str());
        }
    }

    const std::vector<MassSpring::Spring> &
    MassSpring::springs() const
    {
      return spring_list;
    }

    const MassSpring::Report &
    MassSpring::report() const
    {
      return last_report;
    }

    SOFTFACE_REGISTER_MODEL(
      MassSpring,
      "mass spring",
      "Tetrahedral mass spring model (Mollemans et al. 2007, Sec. 2.2): a "
      "spring per edge with Gelder's constants, local "
      "steepest descent with the dynamic cut-out.")
  } // namespace Models
} // namespace softface

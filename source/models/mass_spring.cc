// The mass spring model (models, seed 2.2): a spring per edge with Gelder's
// constants, nonlinear in the positions, and its static equilibrium by local
// steepest descent with the seed's dynamic cut-out.

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/tetrahedron.h>
#include <softface/models/active_set.h>
#include <softface/models/block_colouring.h>
#include <softface/models/mass_spring.h>
#include <softface/models/point_exchange.h>

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
      prm.declare_entry("Stop threshold",
                        "0.001",
                        Patterns::Double(0.),
                        "A point moves while its step |F| / sum(k) of its "
                        "springs exceeds this (mm): the seed's force threshold "
                        "of the dynamic cut-out, independent of E.");
      prm.declare_entry("Maximum step fraction",
                        "0.25",
                        Patterns::Double(0., 0.5),
                        "A point never moves by more than this fraction of its "
                        "shortest spring in one update, so that no spring "
                        "flips.");
      prm.declare_entry("Prevent inversion",
                        "false",
                        Patterns::Bool(),
                        "true halves a step that would turn a tetrahedron "
                        "inside out (up to 8 times, else skips it) and makes "
                        "any inversion an error. false is the seed's model: "
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

      // seed eq. 5: every edge once, with the volume of the tetrahedra that
      // share it (summed at the edge's position (j, k), j < k). With
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

      // A constrained update moves its partner too, further than a block's
      // colour keeps apart: such scenes sweep in plain order on one thread.
      colouring = scene->has_vertex_constraints() ?
                    std::make_unique<BlockColouring>(mesh->n_points()) :
                    std::make_unique<BlockColouring>(mesh->n_points(),
                                                     mesh->row_start,
                                                     mesh->neighbour);
      // On several MPI ranks each moves the points of its blocks (issue 20).
      exchange = point_exchange(*scene, *colouring, *mesh);
    }

    void
    MassSpring::do_solve(const Vector<double> &prescribed,
                         Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("MassSpring::setup() first."));
      const auto        &row_start     = mesh->row_start;
      const auto        &other_end     = mesh->neighbour;
      const auto        &is_free       = mesh->is_free;
      const auto        &tetrahedra    = mesh->tetrahedra;
      const auto        &tet_start     = mesh->tet_start;
      const auto        &tets_of_point = mesh->tets_of_point;
      const auto        &rest_position = mesh->position;
      const unsigned int n             = rest_position.size();
      // The points this rank moves: the free ones, on several MPI ranks
      // those it owns. Every decision to go on or stop is a global one.
      std::vector<char> mine       = points_to_update(*mesh, exchange.get());
      const auto        global_sum = [&](const unsigned long long local) {
        return sum_over_ranks(exchange.get(), local);
      };
      const auto global_max = [&](const double local) {
        return max_over_ranks(exchange.get(), local);
      };
      static_assert(sizeof(Point<3>) == 3 * sizeof(double),
                    "the exchange reads positions as 3 doubles per point");
      // Ghost points that moved in an exchange.
      std::vector<unsigned int> moved_ghosts;

      // Warm start: from the previous plan's answer; the load steps carry
      // the join points from that plan's positions ('start') to this one's.
      const bool            warm = warm_start && last_position.size() == n;
      std::vector<Point<3>> x(warm ? last_position : rest_position);
      Vector<double>        start(prescribed.size());
      if (warm)
        start = last_prescribed;
      Vector<double> motion(prescribed);
      motion -= start;
      // External nodal forces (gravity), if the scene has them.
      const double *const load =
        scene->has_body_force() ? scene->effects.body_force.begin() : nullptr;

      // The force on point j (seed eq. 4) and its shortest spring.
      const auto force = [&](const unsigned int j, double &shortest) {
        Tensor<1, 3> F;
        if (load != nullptr)
          for (unsigned int c = 0; c < 3; ++c)
            F[c] = load[3 * j + c];
        shortest = std::numeric_limits<double>::max();
        for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
          {
            const Spring      &s      = spring_list[spring_of[i]];
            const Tensor<1, 3> d      = x[other_end[i]] - x[j];
            const double       length = d.norm();
            shortest                  = std::min(shortest, length);
            F += s.stiffness * (length - s.rest_length) / length * d;
          }
        return F;
      };

      ActiveSet active(n);
      // Vertex constraints (sliding contact, lips) per point.
      struct PointConstraint
      {
        unsigned int a, b; // b = a without a partner
        Tensor<1, 3> n;
        bool         unilateral;
      };
      std::vector<PointConstraint> constraints;
      std::vector<int>             constraint_of_point;
      if (scene->has_vertex_constraints())
        {
          constraint_of_point.assign(n, -1);
          for (const VertexConstraint &c : scene->effects.vertex_constraints)
            {
              const unsigned int a = scene->vertex_dofs()[c.vertex][0] / 3;
              const unsigned int b =
                c.partner == numbers::invalid_unsigned_int ?
                  a :
                  scene->vertex_dofs()[c.partner][0] / 3;
              constraint_of_point[a] = constraint_of_point[b] =
                constraints.size();
              constraints.push_back(
                {a, b, c.normal / c.normal.norm(), c.unilateral});
            }
        }
      // The step a point's force asks for: F / sum k, never more than a
      // fraction of its shortest spring (so no spring flips in one step).
      const auto free_step = [&](const unsigned int j) {
        double       shortest;
        Tensor<1, 3> step = force(j, shortest) / total_stiffness[j];
        const double size = step.norm();
        if (size > max_step_fraction * shortest)
          step *= max_step_fraction * shortest / size;
        return step;
      };
      double fraction = 0.; // of the bone motion applied
      // Move @p step of point j onto its constraint: a sliding point stays
      // on the bone surface (orthogonal projection: the springs' stiffness
      // at a point is isotropic). A pair moves together (a block update of
      // both points): @p step_other is the partner's step, the two closing
      // their gap weighted by 1 / sum k if it would open below zero.
      // Returns the partner, or numbers::invalid_unsigned_int.
      const auto constrain = [&](const unsigned int j,
                                 Tensor<1, 3>      &step,
                                 Tensor<1, 3>      &step_other) {
        const PointConstraint &c = constraints[constraint_of_point[j]];
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
            const double lambda =
              -gap / (1. / total_stiffness[c.a] + 1. / total_stiffness[c.b]);
            s_a += lambda / total_stiffness[c.a] * c.n;
            s_b -= lambda / total_stiffness[c.b] * c.n;
          }
        return other;
      };

      // Moving the join points all at once can push a bone point past its
      // free neighbours, flipping springs before any free point has moved.
      // The motion is applied in load steps, each shorter than the step
      // bound of the shortest spring at a moving join point.
      double                    largest_motion = 0., shortest_at_join = 1e300;
      std::vector<unsigned int> moving_joins;
      for (unsigned int j = 0; j < n; ++j)
        if (!is_free[j])
          {
            const double length =
              std::sqrt(motion[3 * j] * motion[3 * j] +
                        motion[3 * j + 1] * motion[3 * j + 1] +
                        motion[3 * j + 2] * motion[3 * j + 2]);
            if (length == 0.)
              continue;
            moving_joins.push_back(j);
            largest_motion = std::max(largest_motion, length);
            for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
              if (is_free[other_end[i]])
                shortest_at_join =
                  std::min(shortest_at_join,
                           spring_list[spring_of[i]].rest_length);
          }
      // A bone surface that sliding points follow moves them like join
      // points.
      bool surface_moves = false;
      for (const auto &c : constraints)
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
        moving_joins.empty() && !surface_moves ?
          (load != nullptr ? 1 : 0) :
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
      const unsigned int n_load_steps = steps_needed;

      double initial = 0.;
      for (const unsigned int j : moving_joins)
        for (unsigned int c = 0; c < 3; ++c)
          x[j][c] = rest_position[j][c] + prescribed[3 * j + c];
      for (unsigned int j = 0; j < n; ++j)
        if (is_free[j])
          {
            double shortest;
            initial += force(j, shortest).norm_square();
          }

      Assert(colouring->block_start.back() == n, ExcInternalError());
      const unsigned int                     n_blocks = colouring->n_blocks();
      std::vector<unsigned long long>        block_blocked(n_blocks, 0);
      std::vector<char>                      not_finite(n_blocks, 0);
      std::vector<std::vector<unsigned int>> block_queued(n_blocks);
      unsigned long long                     blocked_updates = 0;
      unsigned int                           sweep           = 0;
      unsigned long long                     point_updates   = 0;
      // On several ranks: each block's updates in a load step, by which the
      // ranks' blocks are shared again for the next. The cut-out works where
      // the motion is, which the first partition, by free points, need not
      // split evenly (a colour waits for its busiest rank), and that region
      // changes from step to step (on the generated cube the ranks made
      // 51:49 of the first step's updates and 2:1 of the tenth's); the last
      // step's work is the best guess at the next's. Any range of blocks
      // makes the serial updates (PointExchange): the answer does not
      // change.
      unsigned int rebalances = 0;
      // The ranks' updates colour by colour.
      ColourUpdates       colour_updates;
      std::vector<double> block_work(exchange && n_load_steps > 1 ? n_blocks :
                                                                    0,
                                     0.);
      for (unsigned int load_step = 1; load_step <= n_load_steps; ++load_step)
        {
          fraction = double(load_step) / n_load_steps;
          // A sliding point follows its bone surface.
          for (const auto &c : constraints)
            active.queue(c.a), active.queue(c.b);
          // The load is there from the start: every free point feels it.
          if (load_step == 1 && load != nullptr)
            for (unsigned int j = 0; j < n; ++j)
              if (mine[j])
                active.queue(j);
          for (const unsigned int j : moving_joins)
            {
              for (unsigned int c = 0; c < 3; ++c)
                x[j][c] = rest_position[j][c] + start[3 * j + c] +
                          fraction * motion[3 * j + c];
              for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
                {
                  const unsigned int k = other_end[i];
                  if (mine[k])
                    active.queue(k);
                }
            }

          // On several ranks a rank with no point to move sweeps on with
          // the others, to exchange.
          for (const std::vector<unsigned int> *current = &active.next_sweep();
               global_sum(current->size()) > 0;
               current = &active.next_sweep())
            {
              if (sweep == max_sweeps)
                {
                  double pending = 0., shortest;
                  for (const unsigned int j : *current)
                    pending =
                      std::max(pending,
                               force(j, shortest).norm() / total_stiffness[j]);
                  pending = global_max(pending);
                  std::ostringstream m;
                  m << "mass spring: " << max_sweeps
                    << " sweeps were not enough (load step " << load_step
                    << " of " << n_load_steps << "); "
                    << global_sum(current->size())
                    << " points are still active, largest pending step "
                    << pending << " mm (threshold " << stop_threshold
                    << " mm).";
                  throw Error(m.str());
                }
              ++sweep;
              point_updates += current->size();
              if (sweep % 1000 == 0)
                {
                  const auto n_active = global_sum(current->size());
                  if (progress != nullptr)
                    *progress
                      << "      sweep " + std::to_string(sweep) +
                           " (load step " + std::to_string(load_step) + " of " +
                           std::to_string(n_load_steps) +
                           "): " + std::to_string(n_active) + " active points\n"
                      << std::flush;
                }
              // The blocks of one colour at once (BlockColouring), each over
              // its points of this sweep in order; the colours in turn.
              const auto block_update = [&](const unsigned int b,
                                            const std::size_t  begin,
                                            const std::size_t  end) {
                std::vector<unsigned int> &queued = block_queued[b];
                if (!block_work.empty())
                  block_work[b] += end - begin;
                for (std::size_t q = begin; q < end; ++q)
                  {
                    const unsigned int j = (*current)[q];
                    {
                      Tensor<1, 3>       step = free_step(j), step_other;
                      const unsigned int partner =
                        (!constraint_of_point.empty() &&
                         constraint_of_point[j] >= 0) ?
                          constrain(j, step, step_other) :
                          numbers::invalid_unsigned_int;
                      const bool paired =
                        partner != numbers::invalid_unsigned_int;
                      const double size =
                        std::max(step.norm(), paired ? step_other.norm() : 0.);
                      if (!(size > stop_threshold))
                        {
                          if (!std::isfinite(size))
                            {
                              // Reported after the sweep (not from a thread).
                              not_finite[b] = 1;
                              return;
                            }
                          continue;
                        }
                      // Springs alone do not keep a tetrahedron from turning
                      // inside out (seed 2.2, disadvantage 1): a step that
                      // would invert one is halved until it does not, or not
                      // taken.
                      const Point<3> old      = x[j];
                      unsigned int   halvings = 0;
                      for (; halvings < 8 && prevent_inversion;
                           ++halvings, step *= 0.5)
                        {
                          x[j]          = old + step;
                          bool inverted = false;
                          for (unsigned int t = tet_start[j];
                               t < tet_start[j + 1] && !inverted;
                               ++t)
                            {
                              const auto &v = tetrahedra[tets_of_point[t]];
                              inverted =
                                Tetrahedron::signed_volume(
                                  {{x[v[0]], x[v[1]], x[v[2]], x[v[3]]}}) <= 0.;
                            }
                          if (!inverted)
                            break;
                        }
                      if (!prevent_inversion)
                        x[j] = old + step;
                      else if (halvings == 8)
                        {
                          x[j] = old;
                          ++block_blocked[b];
                          continue;
                        }
                      // A pair moves together (by as much of its step as j).
                      if (paired)
                        x[partner] +=
                          (prevent_inversion ? std::pow(0.5, halvings) : 1.) *
                          step_other;
                      // Their own forces and their neighbours' have changed.
                      const auto queue_around = [&](const unsigned int moved) {
                        active.queue(moved, queued);
                        for (unsigned int i = row_start[moved];
                             i < row_start[moved + 1];
                             ++i)
                          if (mine[other_end[i]])
                            active.queue(other_end[i], queued);
                      };
                      // A step lost in rounding moved nothing (a stop
                      // threshold of 0): nothing to wake, as a rank that
                      // reads j as a ghost sees (PointExchange).
                      if (paired || x[j] != old)
                        queue_around(j);
                      if (paired)
                        queue_around(partner);
                    }
                  }
              };
              // On several ranks each colour's moves travel before the
              // next colour (PointExchange): the serial sweep. A ghost that
              // moved changed the force on its neighbours here.
              const auto exchange_colour = [&](const unsigned int c,
                                               const std::size_t  n_updated) {
                colour_updates.record(n_updated);
                moved_ghosts.clear();
                exchange->exchange(c, &x[0][0], moved_ghosts);
                for (const unsigned int g : moved_ghosts)
                  for (unsigned int i = row_start[g]; i < row_start[g + 1]; ++i)
                    if (mine[other_end[i]])
                      active.queue(other_end[i]);
              };
              colouring->sweep(
                *current,
                block_update,
                exchange ? std::function<void(unsigned int, std::size_t)>(
                             exchange_colour) :
                           std::function<void(unsigned int, std::size_t)>());
              bool any_not_finite =
                std::find(not_finite.begin(), not_finite.end(), 1) !=
                not_finite.end();
              if (exchange)
                any_not_finite = global_max(any_not_finite) > 0.;
              for (unsigned int b = 0; b < n_blocks; ++b)
                {
                  if (any_not_finite)
                    throw Error("mass spring: the force on a point became "
                                "infinite or NaN (a spring of zero length) "
                                "in sweep " +
                                std::to_string(sweep) + ".");
                  blocked_updates += block_blocked[b];
                  block_blocked[b] = 0;
                  active.add(block_queued[b]);
                }
            }

          // After a load step (no point is pending on any rank): the blocks
          // shared again by its updates (PointExchange adds each block's
          // free points, so that blocks it did not reach still spread).
          if (!block_work.empty() && load_step < n_load_steps)
            {
              const auto timed = phase("rebalance");
              Utilities::MPI::sum(block_work, communicator, block_work);
              // The same on every rank (block_work is): unchanged ranges
              // keep the exchange.
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
                  mine     = points_to_update(*mesh, exchange.get());
                  ++rebalances;
                }
              std::fill(block_work.begin(), block_work.end(), 0.);
            }
        }

      if (exchange)
        {
          const auto timed = phase("gather");
          exchange->gather(&x[0][0]);
          blocked_updates = global_sum(blocked_updates);
        }
      const unsigned long long own_updates = point_updates;
      point_updates                        = global_sum(point_updates);
      displacement.reinit(3 * n);
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int c = 0; c < 3; ++c)
          displacement[3 * j + c] = x[j][c] - rest_position[j][c];

      last_report               = Report();
      last_report.sweeps        = sweep;
      last_report.load_steps    = n_load_steps;
      last_report.point_updates = point_updates;
      double residual           = 0.;
      for (unsigned int j = 0; j < n; ++j)
        if (mine[j])
          {
            double       shortest;
            Tensor<1, 3> F = force(j, shortest);
            // A constrained point: the step it would take under its
            // constraint (what the constraint takes up is no residual).
            if (!constraint_of_point.empty() && constraint_of_point[j] >= 0)
              {
                Tensor<1, 3> step = free_step(j), step_other;
                if (constrain(j, step, step_other) !=
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
          last_report.max_step = global_max(last_report.max_step);
          add_detail("points per rank (largest)",
                     Utilities::MPI::max(exchange->n_owned_points(),
                                         communicator));
          add_detail("ghost points per rank (largest)",
                     Utilities::MPI::max(exchange->n_ghost_points(),
                                         communicator));
          // The dynamic cut-out works where the motion is, which a static
          // partition need not split evenly: a colour waits for the rank
          // with the most updates in it.
          add_detail("busiest rank's point updates",
                     Utilities::MPI::max(own_updates, communicator));
          add_detail("slowest rank's point updates, colour by colour",
                     colour_updates.slowest_sum(communicator));
          // The ranges and ghosts above are the last load step's; the next
          // plan starts from them.
          add_detail("load steps that moved blocks between ranks", rebalances);
        }
      for (const auto &t : tetrahedra)
        last_report.inverted_tetrahedra +=
          (Tetrahedron::signed_volume({{x[t[0]], x[t[1]], x[t[2]], x[t[3]]}}) <=
           0.);

      last_report.blocked_updates = blocked_updates;
      last_report.rebalances      = rebalances;
      set_iterations(sweep);
      set_residual(initial > 0. ? std::sqrt(residual / initial) : 0.);
      if (warm)
        add_detail("warm start", "from the previous plan");
      add_detail("load steps", n_load_steps);
      add_detail("point updates", point_updates);
      add_detail("largest pending step", last_report.max_step, "mm");
      add_detail("blocked updates", blocked_updates);
      add_detail("inverted tetrahedra", last_report.inverted_tetrahedra);
      if (!prevent_inversion && last_report.inverted_tetrahedra > 0 &&
          last_report.max_step <= stop_threshold)
        warn("reached equilibrium with " +
             std::to_string(last_report.inverted_tetrahedra) +
             " inverted tetrahedra (springs flipped over, seed 2.2); the "
             "answer is not physical there.");
      else if (last_report.inverted_tetrahedra > 0 ||
               last_report.max_step > stop_threshold)
        {
          std::ostringstream m;
          m << "mass spring: no equilibrium reached after " << sweep
            << " sweeps in " << n_load_steps << " load steps: largest pending "
            << "step " << last_report.max_step << " mm (threshold "
            << stop_threshold << " mm), " << last_report.inverted_tetrahedra
            << " inverted tetrahedra, " << blocked_updates
            << " updates held back because they would have inverted a "
               "tetrahedron. Springs alone cannot keep tetrahedra from "
               "collapsing under this motion (seed 2.2); refine the mesh or "
               "use another model.";
          throw Error(m.str());
        }
      // The next plan starts here.
      last_position   = x;
      last_prescribed = prescribed;
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

    SOFTFACE_REGISTER_MODEL(MassSpring,
                            "mass spring",
                            "Tetrahedral mass spring model (seed 2.2): a "
                            "spring per edge with Gelder's constants, local "
                            "steepest descent with the dynamic cut-out.")
  } // namespace Models
} // namespace softface

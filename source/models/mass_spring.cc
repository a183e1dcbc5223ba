#include <deal.II/base/timer.h>

#include <softface/models/active_set.h>
#include <softface/core/error.h>
#include <softface/fe/linear_elasticity.h>
#include <softface/core/mesh.h>
#include <softface/models/mass_spring.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace softface
{
  namespace Models
  {
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

    void
    MassSpring::setup(const Scene &scene_in)
    {
      scene = &scene_in;
      stats = Statistics();
      Timer timer;

      if (!scene->dofs_are_point_blocks())
        throw Error("mass spring: the DoFs of a vertex are not a block "
                    "3p, 3p+1, 3p+2 (renumbered DoFs?).");
      const unsigned int n = scene->dof_handler.n_dofs() / 3;
      rest_position.assign(n, Point<3>());
      is_free.assign(n, false);
      for (unsigned int v = 0; v < scene->vertex_dofs().size(); ++v)
        {
          const auto &dofs = scene->vertex_dofs()[v];
          if (dofs[0] == numbers::invalid_dof_index)
            continue;
          rest_position[dofs[0] / 3] = scene->triangulation.get_vertices()[v];
          is_free[dofs[0] / 3]       = !scene->join_dofs()[dofs[0]];
        }

      // seed eq. 5: every edge once, with the volume of the tetrahedra that
      // share it.
      std::map<std::pair<unsigned int, unsigned int>, double> edge_volume;
      tetrahedra.clear();
      for (const auto &cell : scene->triangulation.active_cell_iterators())
        {
          std::array<unsigned int, 4> p;
          for (unsigned int a = 0; a < 4; ++a)
            p[a] = scene->vertex_dofs()[cell->vertex_index(a)][0] / 3;
          tetrahedra.push_back(p);
          const double volume =
            Mesh::signed_volume(LinearElasticity::cell_vertices(cell));
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int b = a + 1; b < 4; ++b)
              edge_volume[{std::min(p[a], p[b]), std::max(p[a], p[b])}] +=
                volume;
        }
      const double E = scene->material.youngs_modulus();
      spring_list.clear();
      spring_list.reserve(edge_volume.size());
      for (const auto &[edge, volume] : edge_volume)
        {
          const double L0 =
            rest_position[edge.first].distance(rest_position[edge.second]);
          spring_list.push_back(
            {edge.first, edge.second, L0, E * volume / (L0 * L0)});
        }

      std::vector<unsigned int> count(n + 1, 0);
      for (const Spring &s : spring_list)
        ++count[s.a + 1], ++count[s.b + 1];
      row_start.assign(n + 1, 0);
      for (unsigned int j = 0; j < n; ++j)
        row_start[j + 1] = row_start[j] + count[j + 1];
      other_end.resize(2 * spring_list.size());
      spring_of.resize(2 * spring_list.size());
      std::vector<unsigned int> fill(row_start.begin(), row_start.end() - 1);
      total_stiffness.assign(n, 0.);
      for (unsigned int i = 0; i < spring_list.size(); ++i)
        {
          const Spring &s      = spring_list[i];
          other_end[fill[s.a]] = s.b, spring_of[fill[s.a]++] = i;
          other_end[fill[s.b]] = s.a, spring_of[fill[s.b]++] = i;
          total_stiffness[s.a] += s.stiffness;
          total_stiffness[s.b] += s.stiffness;
        }

      tet_start.assign(n + 1, 0);
      for (const auto &t : tetrahedra)
        for (const unsigned int p : t)
          ++tet_start[p + 1];
      for (unsigned int j = 0; j < n; ++j)
        tet_start[j + 1] += tet_start[j];
      tets_of_point.resize(tet_start[n]);
      std::vector<unsigned int> next_slot(tet_start.begin(),
                                          tet_start.end() - 1);
      for (unsigned int t = 0; t < tetrahedra.size(); ++t)
        for (const unsigned int p : tetrahedra[t])
          tets_of_point[next_slot[p]++] = t;

      stats.setup_time = timer.wall_time();
      stats.phases.emplace_back("springs", stats.setup_time);
      stats.details.emplace_back("springs", std::to_string(spring_list.size()));
    }

    void
    MassSpring::solve(const Vector<double> &prescribed,
                      Vector<double>       &displacement)
    {
      Assert(scene != nullptr, ExcMessage("MassSpring::setup() first."));
      Timer              timer;
      const unsigned int n = rest_position.size();

      std::vector<Point<3>> x(rest_position);

      // The force on point j (seed eq. 4) and its shortest spring.
      const auto force = [&](const unsigned int j, double &shortest) {
        Tensor<1, 3> F;
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

      // Moving the join points all at once can push a bone point past its
      // free neighbours, flipping springs before any free point has moved.
      // The motion is applied in load steps, each shorter than the step
      // bound of the shortest spring at a moving join point.
      double                    largest_motion = 0., shortest_at_join = 1e300;
      std::vector<unsigned int> moving_joins;
      for (unsigned int j = 0; j < n; ++j)
        if (!is_free[j])
          {
            const double motion =
              std::sqrt(prescribed[3 * j] * prescribed[3 * j] +
                        prescribed[3 * j + 1] * prescribed[3 * j + 1] +
                        prescribed[3 * j + 2] * prescribed[3 * j + 2]);
            if (motion == 0.)
              continue;
            moving_joins.push_back(j);
            largest_motion = std::max(largest_motion, motion);
            for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
              if (is_free[other_end[i]])
                shortest_at_join =
                  std::min(shortest_at_join,
                           spring_list[spring_of[i]].rest_length);
          }
      const unsigned int n_load_steps =
        moving_joins.empty() ?
          0 :
          std::max(1.,
                   std::ceil(largest_motion /
                             (max_step_fraction * shortest_at_join)));

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

      ActiveSet          active(n);
      unsigned long long blocked_updates = 0;
      unsigned int       sweep           = 0;
      unsigned long long point_updates   = 0;
      for (unsigned int load_step = 1; load_step <= n_load_steps; ++load_step)
        {
          const double fraction = double(load_step) / n_load_steps;
          for (const unsigned int j : moving_joins)
            {
              for (unsigned int c = 0; c < 3; ++c)
                x[j][c] =
                  rest_position[j][c] + fraction * prescribed[3 * j + c];
              for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
                {
                  const unsigned int k = other_end[i];
                  if (is_free[k])
                    active.queue(k);
                }
            }

          for (const std::vector<unsigned int> *current = &active.next_sweep();
               !current->empty();
               current = &active.next_sweep())
            {
              if (sweep == max_sweeps)
                {
                  double pending = 0., shortest;
                  for (const unsigned int j : *current)
                    pending =
                      std::max(pending,
                               force(j, shortest).norm() / total_stiffness[j]);
                  std::ostringstream m;
                  m << "mass spring: " << max_sweeps
                    << " sweeps were not enough (load step " << load_step
                    << " of " << n_load_steps << "); " << current->size()
                    << " points are still active, largest pending step "
                    << pending << " mm (threshold " << stop_threshold
                    << " mm).";
                  throw Error(m.str());
                }
              ++sweep;
              point_updates += current->size();
              if (progress != nullptr && sweep % 1000 == 0)
                *progress << "      sweep " + std::to_string(sweep) +
                               " (load step " + std::to_string(load_step) +
                               " of " + std::to_string(n_load_steps) +
                               "): " + std::to_string(current->size()) +
                               " active points\n"
                          << std::flush;
              for (const unsigned int j : *current)
                {
                  double             shortest;
                  const Tensor<1, 3> F    = force(j, shortest);
                  Tensor<1, 3>       step = F / total_stiffness[j];
                  const double       size = step.norm();
                  if (!(size > stop_threshold))
                    {
                      if (!std::isfinite(size))
                        throw Error("mass spring: the force on a point "
                                    "became infinite or NaN (a spring of "
                                    "zero length) in sweep " +
                                    std::to_string(sweep) + ".");
                      continue;
                    }
                  if (size > max_step_fraction * shortest)
                    step *= max_step_fraction * shortest / size;
                  // Springs alone do not keep a tetrahedron from turning
                  // inside out (seed 2.2, disadvantage 1): a step that would
                  // invert one is halved until it does not, or not taken.
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
                            Mesh::signed_volume(
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
                      ++blocked_updates;
                      continue;
                    }
                  // Its own force and its neighbours' forces have changed.
                  active.queue(j);
                  for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
                    if (is_free[other_end[i]])
                      active.queue(other_end[i]);
                }
            }
        }

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
        if (is_free[j])
          {
            double       shortest;
            const double f = force(j, shortest).norm();
            last_report.max_step =
              std::max(last_report.max_step, f / total_stiffness[j]);
            residual += f * f;
          }
      for (const auto &t : tetrahedra)
        last_report.inverted_tetrahedra +=
          (Mesh::signed_volume({{x[t[0]], x[t[1]], x[t[2]], x[t[3]]}}) <= 0.);

      stats.iterations = sweep;
      stats.residual   = initial > 0. ? std::sqrt(residual / initial) : 0.;
      stats.solve_time = timer.wall_time();
      stats.details.resize(1);
      stats.details.emplace_back("load steps", std::to_string(n_load_steps));
      stats.details.emplace_back("point updates",
                                 std::to_string(point_updates));
      std::ostringstream s;
      s << std::setprecision(3) << last_report.max_step << " mm";
      stats.details.emplace_back("largest pending step", s.str());
      stats.details.emplace_back("blocked updates",
                                 std::to_string(blocked_updates));
      stats.details.emplace_back(
        "inverted tetrahedra", std::to_string(last_report.inverted_tetrahedra));
      last_report.blocked_updates = blocked_updates;
      if (!prevent_inversion && last_report.inverted_tetrahedra > 0 &&
          last_report.max_step <= stop_threshold)
        std::cerr << "softface: warning: mass spring reached equilibrium with "
                  << last_report.inverted_tetrahedra
                  << " inverted tetrahedra (springs flipped over, seed 2.2); "
                     "the answer is not physical there."
                  << std::endl;
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

// A scene ready for interactive planning (serve): every offered model's
// response basis built once, then a plan from the page's sliders becomes the
// shown surface's displacement by one combination and step B of the skin
// mapping.

#include <deal.II/base/timer.h>

#include <softface/core/error.h>
#include <softface/core/planning.h>
#include <softface/core/rigid_motion.h>
#include <softface/core/threads.h>
#include <softface/outputs/skin_output.h>
#include <softface/serve/interactive_planner.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace Serve
  {
    namespace
    {
      // The rotation by angles[0], angles[1], angles[2] degrees about x, y
      // and z in turn (R = Rz Ry Rx) as an axis and an angle.
      std::pair<Tensor<1, 3>, double>
      axis_and_angle(const double angles[3])
      {
        Tensor<2, 3> R = unit_symmetric_tensor<3>();
        for (unsigned int a = 0; a < 3; ++a)
          {
            const double       c = std::cos(angles[a] * M_PI / 180.);
            const double       s = std::sin(angles[a] * M_PI / 180.);
            const unsigned int i = (a + 1) % 3, j = (a + 2) % 3;
            Tensor<2, 3>       Ra = unit_symmetric_tensor<3>();
            Ra[i][i]              = c;
            Ra[i][j]              = -s;
            Ra[j][i]              = s;
            Ra[j][j]              = c;
            R                     = Ra * R;
          }
        const double cosine = std::clamp((trace(R) - 1.) / 2., -1., 1.);
        const double angle  = std::acos(cosine);
        Tensor<1, 3> axis;
        axis[0] = R[2][1] - R[1][2];
        axis[1] = R[0][2] - R[2][0];
        axis[2] = R[1][0] - R[0][1];
        if (angle < 1e-10 || axis.norm() == 0.)
          return {Tensor<1, 3>({0., 0., 1.}), 0.};
        return {axis / axis.norm(), angle * 180. / M_PI};
      }
    } // namespace

    InteractivePlanner::InteractivePlanner(const std::string &scene_file,
                                           std::ostream      &out)
    {
      simulator.prepare(scene_file, out);
      const Scene &scene = simulator.scene();
      try
        {
          serve_parameters.parse_parameters(simulator.parameters());
        }
      catch (const Error &e)
        {
          throw Error(scene_file + ": " + e.what());
        }

      const Planning &base = simulator.plannings().plans[0].planning;
      segment_indices      = base.moved_segments();
      for (const unsigned int s : segment_indices)
        {
          const auto &c = scene.segments[s].join_centroid;
          segments.push_back(
            {scene.segments[s].name,
             c.size() == 3 ? Point<3>(c[0], c[1], c[2]) : Point<3>()});
        }
      if (segments.empty())
        throw Error(scene_file +
                    ": Planning/Moved segments is empty: nothing to move.");

      // The surface shown: the dense skin, or the mesh's outer surface.
      SkinOutput *skin = simulator.skin();
      if (skin != nullptr)
        {
          shown               = skin->skin_surface();
          post                = skin->post_operative_surface();
          kind                = "dense skin";
          const auto &weights = skin->mapping();
          for (unsigned int i = 0; i < shown.points.size(); ++i)
            if (weights.row_start[i + 1] > weights.row_start[i])
              moving.push_back(i);
        }
      else
        {
          const auto mesh =
            SurfaceMapping::VolumeMesh::from_triangulation(scene.triangulation,
                                                           {});
          std::vector<unsigned int> point_of_vertex(
            mesh.vertices.size(), numbers::invalid_unsigned_int);
          for (const auto &triangle : mesh.skin.triangles)
            {
              std::array<unsigned int, 3> t;
              for (unsigned int k = 0; k < 3; ++k)
                {
                  unsigned int &p = point_of_vertex[triangle[k]];
                  if (p == numbers::invalid_unsigned_int)
                    {
                      p = shown.points.size();
                      shown.points.push_back(mesh.vertices[triangle[k]]);
                      mesh_vertex_of_point.push_back(triangle[k]);
                    }
                  t[k] = p;
                }
              shown.triangles.push_back(t);
            }
          kind             = "mesh surface";
          const auto moved = [this](const unsigned int segment) {
            return std::find(segment_indices.begin(),
                             segment_indices.end(),
                             segment) != segment_indices.end();
          };
          for (unsigned int i = 0; i < mesh_vertex_of_point.size(); ++i)
            {
              const unsigned int segment =
                scene.vertex_segment()[mesh_vertex_of_point[i]];
              if (segment == numbers::invalid_unsigned_int || moved(segment))
                moving.push_back(i);
            }
        }

      // Distances to the post-operative skin: the tree once, every point at
      // rest once (the points that never move keep theirs).
      if (!post.points.empty())
        {
          Timer timer;
          distance_to_post = std::make_unique<Validation::SignedDistance>(post);
          rest_distance.resize(shown.points.size());
          distances([this](const unsigned int i) { return shown.points[i]; },
                    rest_distance);
          out << "  post-operative skin: " << post.points.size()
              << " points; distances at rest " << std::setprecision(3)
              << timer.wall_time() << " s" << std::endl;
        }

      // Each offered model: set up, its basis built, then freed.
      auto &models = simulator.models();
      for (const std::string &name : serve_parameters.models)
        {
          auto model =
            std::find_if(models.begin(), models.end(), [&](const auto &m) {
              return m.first == name;
            });
          if (model == models.end())
            throw Error(scene_file + ": Serve/Models: '" + name +
                        "' is not among Models/Models.");
          if (!model->second)
            throw Error(scene_file + ": Serve/Models: '" + name +
                        "' is listed twice.");
          if (!model->second->linear_in_motion(scene))
            throw Error(scene_file + ": Serve/Models: '" + name +
                        "' has no response basis (its answer is not linear "
                        "in the motion on this scene); offer linear fem or "
                        "mass tensor.");
          Timer timer;
          model->second->setup(scene);
          const double setup = timer.wall_time();
          auto         basis = std::make_unique<Models::ResponseBasis>();
          basis->build(*model->second, scene, segment_indices);
          out << "  " << name << ": setup " << std::setprecision(3) << setup
              << " s, response basis " << timer.wall_time() - setup << " s ("
              << Models::ResponseBasis::n_solves(scene, segments.size())
              << " solves, " << basis->memory_mb() << " MB)" << std::endl;
          names.push_back(name);
          bases.push_back(std::move(basis));
          model->second.reset();
        }
    }

    InteractivePlanner::~InteractivePlanner() = default;

    const Parameters &
    InteractivePlanner::parameters() const
    {
      return serve_parameters;
    }

    const std::vector<InteractivePlanner::Segment> &
    InteractivePlanner::moved_segments() const
    {
      return segments;
    }

    std::vector<std::string>
    InteractivePlanner::model_names() const
    {
      return names;
    }

    const SurfaceMapping::Surface &
    InteractivePlanner::surface() const
    {
      return shown;
    }

    const SurfaceMapping::Surface &
    InteractivePlanner::post_operative() const
    {
      return post;
    }

    const std::vector<unsigned int> &
    InteractivePlanner::moving_points() const
    {
      return moving;
    }

    const std::vector<float> &
    InteractivePlanner::rest_distances() const
    {
      return rest_distance;
    }

    void
    InteractivePlanner::distances(
      const std::function<Point<3>(unsigned int)> &point,
      std::vector<float>                          &distance) const
    {
      // Independent queries, in ranges on the threads.
      const unsigned int n     = distance.size();
      const unsigned int range = 4096;
      Threads::run_tasks((n + range - 1) / range, [&](const unsigned int t) {
        for (unsigned int k = t * range; k < std::min(n, (t + 1) * range); ++k)
          distance[k] = (*distance_to_post)(point(k));
      });
    }

    const std::string &
    InteractivePlanner::surface_kind() const
    {
      return kind;
    }

    InteractivePlanner::Result
    InteractivePlanner::replan(const std::string         &model,
                               const std::vector<Motion> &motions,
                               const bool                 with_distance) const
    {
      const auto m = std::find(names.begin(), names.end(), model);
      if (m == names.end())
        throw Error("unknown model '" + model + "'.");
      if (motions.size() != segments.size())
        throw Error("a plan needs " + std::to_string(segments.size()) +
                    " motions (one per moved segment), not " +
                    std::to_string(motions.size()) + ".");

      Planning planning;
      for (unsigned int s = 0; s < segments.size(); ++s)
        {
          const Motion &motion = motions[s];
          for (unsigned int k = 0; k < 6; ++k)
            {
              const double limit = k < 3 ? serve_parameters.translation_limit :
                                           serve_parameters.rotation_limit;
              if (!std::isfinite(motion[k]))
                throw Error("segment '" + segments[s].name +
                            "': a motion entry is not a finite number.");
              if (std::abs(motion[k]) > limit)
                {
                  std::ostringstream message;
                  message << "segment '" << segments[s].name
                          << "': " << (k < 3 ? "translation " : "rotation ")
                          << motion[k] << (k < 3 ? " mm" : " degrees")
                          << " is past the limit of " << limit << " (Serve/"
                          << (k < 3 ? "Translation" : "Rotation") << " limit).";
                  throw Error(message.str());
                }
            }
          const auto [axis, angle] = axis_and_angle(&motion[3]);
          planning.set_motion(segment_indices[s],
                              RigidMotion(Tensor<1, 3>(
                                            {motion[0], motion[1], motion[2]}),
                                          axis,
                                          angle,
                                          segments[s].centre));
        }

      Result         result;
      Timer          timer;
      Vector<double> u;
      bases[m - names.begin()]->combine(planning, u);
      result.combination_ms = 1e3 * timer.wall_time();

      timer.restart();
      const Scene &scene = simulator.scene();
      result.displacement.resize(3 * moving.size());
      if (mesh_vertex_of_point.empty())
        {
          std::vector<Tensor<1, 3>> skin_u;
          simulator.skin()->map(scene, u, skin_u);
          for (unsigned int k = 0; k < moving.size(); ++k)
            for (unsigned int c = 0; c < 3; ++c)
              result.displacement[3 * k + c] = skin_u[moving[k]][c];
        }
      else
        for (unsigned int k = 0; k < moving.size(); ++k)
          for (unsigned int c = 0; c < 3; ++c)
            result.displacement[3 * k + c] =
              u[scene.vertex_dofs()[mesh_vertex_of_point[moving[k]]][c]];
      result.mapping_ms = 1e3 * timer.wall_time();

      if (with_distance && distance_to_post)
        {
          timer.restart();
          // Only the moving points, displaced.
          const float *const u = result.displacement.data();
          result.distance.resize(moving.size());
          distances(
            [&](const unsigned int k) {
              return shown.points[moving[k]] +
                     Tensor<1, 3>({u[3 * k], u[3 * k + 1], u[3 * k + 2]});
            },
            result.distance);
          result.distance_ms = 1e3 * timer.wall_time();
        }
      return result;
    }
  } // namespace Serve
} // namespace softface

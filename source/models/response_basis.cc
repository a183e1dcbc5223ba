// Every plan as a combination of 12 responses per moved segment (models):
// the join displacement of a rigid motion is linear in (R - I, t), so a
// model whose answer is affine in it needs 12 solves per segment once, and
// then a plan costs one pass over the responses.

#include <softface/core/error.h>
#include <softface/core/threads.h>
#include <softface/models/response_basis.h>

#include <algorithm>

namespace softface
{
  namespace Models
  {
    unsigned int
    ResponseBasis::n_solves(const Scene &scene, const unsigned int n_segments)
    {
      return 12 * n_segments + (scene.has_body_force() ? 1 : 0);
    }

    void
    ResponseBasis::build(Interface                       &model,
                         const Scene                     &scene_in,
                         const std::vector<unsigned int> &segments_in)
    {
      if (!model.linear_in_motion(scene_in))
        throw Error("a response basis needs a model whose answer is linear "
                    "in the motion (linear fem or mass tensor, without "
                    "unilateral contact).");
      scene    = &scene_in;
      segments = segments_in;
      centre.clear();
      responses.clear();
      offset.reinit(0);
      total_iterations = 0;
      largest_residual = 0.;
      warnings.clear();

      std::string current; // which response, for messages
      const auto  solve = [&](const Vector<double> &prescribed) {
        Vector<double>    u;
        const PlanContext silent{LoadPath(), nullptr, nullptr, true};
        try
          {
            model.solve(prescribed, u, silent);
          }
        catch (const std::exception &e)
          {
            throw Error("response basis (" + current + "): " + e.what());
          }
        for (const auto &warning : model.statistics().warnings)
          if (std::find(warnings.begin(), warnings.end(), warning) ==
              warnings.end())
            warnings.push_back(warning);
        total_iterations += model.statistics().iterations;
        largest_residual =
          std::max(largest_residual, model.statistics().residual);
        return u;
      };
      current = "the body force alone";
      if (scene->has_body_force())
        offset = solve(Vector<double>(scene->n_dofs()));

      for (const unsigned int s : segments)
        {
          const auto &c = scene->segments[s].join_centroid;
          centre.push_back(c.size() == 3 ? Point<3>(c[0], c[1], c[2]) :
                                           Point<3>());
          const Point<3> c_s = centre.back();
          // A model that stops on absolute figures (the mass tensor model's
          // mm per sweep) answers a motion of 1 mm only to within them: each
          // response is solved for a motion of about 'typical_motion' at the
          // join points (a plan's size) and scaled back.
          double reach = 0.;
          {
            const auto &vertices = scene->vertices();
            for (unsigned int v = 0; v < vertices.size(); ++v)
              if (scene->vertex_segment()[v] == s)
                for (unsigned int d = 0; d < 3; ++d)
                  reach = std::max(reach, std::abs((vertices[v] - c_s)[d]));
          }
          for (unsigned int k = 0; k < 12; ++k)
            {
              // k < 9: d_i(x) = (x - c_s)_j with k = 3 i + j; else the
              // unit translation along k - 9.
              const double scale =
                typical_motion / (k < 9 && reach > 0. ? reach : 1.);
              const auto unit = [k, s, c_s, scale](const unsigned int segment,
                                                   const Point<3>    &x) {
                Tensor<1, 3> d;
                if (segment != s)
                  return d;
                if (k < 9)
                  d[k / 3] = scale * (x - c_s)[k % 3];
                else
                  d[k - 9] = scale;
                return d;
              };
              current = "segment '" + scene->segments[s].name + "', " +
                        (k < 9 ? "(R - I) entry " + std::to_string(k / 3) +
                                   std::to_string(k % 3) :
                                 "translation " + std::to_string(k - 9));
              Vector<double> r =
                solve(Planning::join_displacement(*scene, {s}, unit));
              if (offset.size() != 0)
                r -= offset;
              r /= scale;
              responses.push_back(std::move(r));
            }
        }
    }

    void
    ResponseBasis::combine(const Planning &planning,
                           Vector<double> &displacement) const
    {
      Assert(scene != nullptr, ExcMessage("ResponseBasis::build() first."));
      for (const unsigned int s : planning.moved_segments())
        if (std::find(segments.begin(), segments.end(), s) == segments.end())
          throw Error("the plan moves segment '" + scene->segments[s].name +
                      "', which the response basis was not built for.");

      // The plan's entries and their responses, zeros left out (a pure
      // translation has 3).
      std::vector<double>                 weight;
      std::vector<const Vector<double> *> response;
      for (unsigned int i = 0; i < segments.size(); ++i)
        {
          const RigidMotion  motion = planning.motion(segments[i]);
          const Point<3>     c_s    = centre[i];
          const Tensor<1, 3> t_s    = motion.displacement(c_s);
          double             entry[12];
          for (unsigned int j = 0; j < 3; ++j)
            {
              Point<3> e = c_s;
              e[j] += 1.;
              // Column j of R: the image of c_s + e_j less that of c_s.
              const Tensor<1, 3> column = motion(e) - motion(c_s);
              for (unsigned int r = 0; r < 3; ++r)
                entry[3 * r + j] = column[r] - (r == j ? 1. : 0.);
            }
          for (unsigned int d = 0; d < 3; ++d)
            entry[9 + d] = t_s[d];
          for (unsigned int k = 0; k < 12; ++k)
            if (entry[k] != 0.)
              {
                weight.push_back(entry[k]);
                response.push_back(&responses[12 * i + k]);
              }
        }

      const unsigned int n = scene->n_dofs();
      displacement.reinit(n, /*omit_zeroing_entries=*/true);
      // One pass, in contiguous ranges on the threads: every entry is
      // written once from the same terms in the same order.
      const unsigned int range   = 16384;
      const unsigned int n_tasks = (n + range - 1) / range;
      Threads::run_tasks(n_tasks, [&](const unsigned int task) {
        const unsigned int begin = task * range;
        const unsigned int end   = std::min(n, begin + range);
        double *const      u     = displacement.begin();
        if (offset.size() != 0)
          std::copy(offset.begin() + begin, offset.begin() + end, u + begin);
        else
          std::fill(u + begin, u + end, 0.);
        for (unsigned int k = 0; k < weight.size(); ++k)
          {
            const double        w = weight[k];
            const double *const r = response[k]->begin();
            for (unsigned int i = begin; i < end; ++i)
              u[i] += w * r[i];
          }
      });
    }

    double
    ResponseBasis::memory_mb() const
    {
      double bytes = offset.size() * sizeof(double);
      for (const auto &r : responses)
        bytes += r.size() * sizeof(double);
      return bytes / (1024. * 1024.);
    }
  } // namespace Models
} // namespace softface

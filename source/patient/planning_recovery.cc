// Planning from a post-operative skull (patient; Mollemans et al. 2007,
// Sec. 3.2): the surface of every bone part of the osteotomy, registered to the
// post-operative skull by ICP from a rough plan, and the recovered motions
// written as a Planning section that a scene includes. For phantom patients,
// whose post-operative CT does not exist, a post-operative skull is made by
// moving each part.

#include <softface/core/error.h>
#include <softface/patient/osteotomy.h>
#include <softface/patient/planning_recovery.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    std::vector<TriangleSurface>
    bone_part_surfaces(const LabelVolume &parts, const unsigned int n_segments)
    {
      std::vector<TriangleSurface> surfaces;
      for (unsigned int s = 0; s < n_segments; ++s)
        {
          Volume<float> mask;
          mask.reinit_like(parts);
          std::size_t n = 0;
          for (std::size_t v = 0; v < parts.n_voxels(); ++v)
            {
              // Detached bone is its part's too.
              const bool in_part = part_number(parts.values[v]) == s + 1;
              mask.values[v]     = in_part;
              n += in_part;
            }
          if (n == 0)
            throw Error("Bone part " + std::to_string(s + 1) +
                        " has no voxel in the bone parts volume.");
          surfaces.push_back(iso_surface(mask, 0.5, false, 20));
        }
      return surfaces;
    }

    TriangleSurface
    moved_skull(const std::vector<TriangleSurface> &parts,
                const std::vector<RigidTransform>  &motions)
    {
      TriangleSurface skull;
      for (unsigned int s = 0; s < parts.size(); ++s)
        {
          const unsigned int offset = skull.points.size();
          for (const auto &x : parts[s].points)
            skull.points.push_back(motions[s](x));
          for (const auto &t : parts[s].triangles)
            skull.triangles.push_back(
              {{t[0] + offset, t[1] + offset, t[2] + offset}});
        }
      return skull;
    }

    std::vector<IcpResult>
    recover_motions(const std::vector<TriangleSurface> &parts,
                    const TriangleSurface              &post_operative,
                    const std::vector<RigidTransform>  &start,
                    const IcpParameters                &parameters)
    {
      std::vector<IcpResult> results;
      for (unsigned int s = 0; s < parts.size(); ++s)
        results.push_back(icp(parts[s].points,
                              post_operative.points,
                              s < start.size() ? start[s] : RigidTransform(),
                              parameters));
      return results;
    }

    std::string
    planning_section(const std::vector<std::string>     &names,
                     const std::vector<IcpResult>       &motions,
                     const std::vector<TriangleSurface> &parts,
                     const double                        tolerance)
    {
      std::ostringstream body, moved;
      body << std::setprecision(10);
      for (unsigned int s = 0; s < names.size(); ++s)
        {
          const RigidTransform &t       = motions[s].transform;
          double                largest = 0.;
          for (const auto &x : parts[s].points)
            {
              const Vec3 y = t(x);
              largest =
                std::max(largest,
                         std::hypot(y[0] - x[0], y[1] - x[1], y[2] - x[2]));
            }
          body << "  # " << names[s] << ": ICP " << motions[s].iterations
               << " iterations, " << motions[s].n_pairs << " pairs, rms "
               << std::setprecision(3) << motions[s].rms << " mm, "
               << (motions[s].converged ? "converged" : "NOT converged")
               << "; largest motion of its surface " << largest << " mm"
               << std::setprecision(10) << '\n';
          if (largest <= tolerance)
            continue;
          moved << (moved.tellp() > 0 ? ", " : "") << names[s];
          // Round-off (1e-17 mm) printed as 0.
          const auto clean = [](const double x) {
            return std::abs(x) < 1e-12 ? 0. : x;
          };
          const Vec3 axis = t.axis();
          body << "  subsection Motion " << names[s] << '\n'
               << "    set Rotation angle  = " << clean(t.angle_degrees())
               << '\n'
               << "    set Rotation axis   = " << clean(axis[0]) << ", "
               << clean(axis[1]) << ", " << clean(axis[2]) << '\n'
               << "    set Rotation centre = 0, 0, 0\n"
               << "    set Translation     = " << clean(t.translation[0])
               << ", " << clean(t.translation[1]) << ", "
               << clean(t.translation[2]) << '\n'
               << "  end\n";
        }
      std::ostringstream out;
      out << "# Recovered from a post-operative skull by ICP (softface "
             "plan).\nsubsection Planning\n"
          << "  set Moved segments = " << moved.str() << '\n'
          << body.str() << "end\n";
      return out.str();
    }
  } // namespace Patient
} // namespace softface

// The preview's 3D views of the bone parts (bone_view.h): a software
// z-buffer, since the machines softface runs on often have no display and
// no OpenGL; an orthographic view with a light from the viewer is enough
// to see which part a piece of bone went to.

#include <softface/patient/bone_view.h>
#include <softface/patient/preview_colours.h>
#include <softface/patient/raster.h>
#include <softface/patient/slice_picture.h>
#include <softface/patient/surface.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      namespace C = PreviewColours;

      constexpr long margin_left = 80, margin_top = 60;

      // The part a surface point belongs to: the most frequent bone value
      // of the 2 x 2 x 2 voxels around it (the surface runs between bone
      // and not bone), or, if none is bone (the blurred surface lies a
      // little outside the bone), of the 4 x 4 x 4 voxels around it.
      std::uint8_t
      part_at(const LabelVolume &parts, const Vec3 &x)
      {
        const Vec3 c = parts.continuous_index(x);
        for (const int reach : {1, 2})
          {
            std::map<std::uint8_t, int> count;
            for (int k = 1 - reach; k <= reach; ++k)
              for (int j = 1 - reach; j <= reach; ++j)
                for (int i = 1 - reach; i <= reach; ++i)
                  {
                    const long ijk[3] = {long(std::floor(c[0])) + i,
                                         long(std::floor(c[1])) + j,
                                         long(std::floor(c[2])) + k};
                    bool       inside = true;
                    for (unsigned int d = 0; d < 3; ++d)
                      inside &= ijk[d] >= 0 && ijk[d] < long(parts.size[d]);
                    if (inside && parts(ijk[0], ijk[1], ijk[2]) != 0)
                      ++count[parts(ijk[0], ijk[1], ijk[2])];
                  }
            std::uint8_t best   = 0;
            int          best_n = 0;
            for (const auto &[value, n] : count)
              if (n > best_n)
                best = value, best_n = n;
            if (best_n > 0)
              return best;
          }
        return 0;
      }

      Colour
      colour_of(const std::uint8_t value, const bool split)
      {
        if (!split || value == 0)
          return C::bone;
        if (is_detached(value))
          return C::detached;
        return C::part(value - 1);
      }

      // The screen axes of a view: (h, v) of a point, and its depth
      // (smaller is nearer).
      struct Projection
      {
        BoneViewSide side;
        VolumeBounds bounds;
        double       pixels_per_mm;

        std::array<double, 3>
        operator()(const Vec3 &x) const
        {
          const unsigned int h     = side == BoneViewSide::front ? 0 : 1;
          const double       depth = side == BoneViewSide::front ? x[1] : -x[0];
          return {{margin_left + (x[h] - bounds.lower[h]) * pixels_per_mm,
                   margin_top + (bounds.upper[2] - x[2]) * pixels_per_mm,
                   depth}};
        }
      };

      // A triangle's normal times twice its area.
      Vec3
      area_normal(const std::array<Vec3, 3> &corner)
      {
        Vec3 u, v;
        for (unsigned int d = 0; d < 3; ++d)
          u[d] = corner[1][d] - corner[0][d],
          v[d] = corner[2][d] - corner[0][d];
        return {{u[1] * v[2] - u[2] * v[1],
                 u[2] * v[0] - u[0] * v[2],
                 u[0] * v[1] - u[1] * v[0]}};
      }

      // One triangle into the z-buffer, shaded by the cosine between the
      // surface's normal and the direction of view (either side: the
      // surface's orientation does not matter here), interpolated from its
      // corners' normals: the voxels' steps of a marching-cubes surface
      // would otherwise show as terraces.
      void
      draw_triangle(Raster                      &raster,
                    std::vector<double>         &depth,
                    const long                   width,
                    const std::array<Vec3, 3>   &corner,
                    const std::array<double, 3> &lambert,
                    const Projection            &project,
                    const Colour                &colour)
      {
        const auto a = project(corner[0]), b = project(corner[1]),
                   c = project(corner[2]);
        const double area =
          (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if (std::abs(area) < 1e-12)
          return;
        const long x0 = std::floor(std::min({a[0], b[0], c[0]}));
        const long x1 = std::ceil(std::max({a[0], b[0], c[0]}));
        const long y0 = std::floor(std::min({a[1], b[1], c[1]}));
        const long y1 = std::ceil(std::max({a[1], b[1], c[1]}));
        for (long y = y0; y <= y1; ++y)
          for (long x = x0; x <= x1; ++x)
            {
              if (!raster.inside(x, y))
                continue;
              // Barycentric coordinates of the pixel's centre.
              const double wa =
                ((b[0] - x) * (c[1] - y) - (c[0] - x) * (b[1] - y)) / area;
              const double wb =
                ((c[0] - x) * (a[1] - y) - (a[0] - x) * (c[1] - y)) / area;
              const double wc = 1. - wa - wb;
              if (wa < 0. || wb < 0. || wc < 0.)
                continue;
              const double z = wa * a[2] + wb * b[2] + wc * c[2];
              auto        &d = depth[y * width + x];
              if (z < d)
                {
                  d = z;
                  const double shade =
                    0.2 +
                    0.8 * (wa * lambert[0] + wb * lambert[1] + wc * lambert[2]);
                  Colour shaded;
                  for (unsigned int k = 0; k < 3; ++k)
                    shaded[k] =
                      static_cast<std::uint8_t>(std::lround(shade * colour[k]));
                  raster.set(x, y, shaded);
                }
            }
      }

      // Title, sides, scale bar and legend around the view.
      void
      draw_frame(Raster                         &raster,
                 const Projection               &project,
                 const long                      width,
                 const long                      height,
                 const std::vector<SegmentSeed> &segments)
      {
        const bool front = project.side == BoneViewSide::front;
        raster.text(margin_left,
                    10,
                    front ? "bone parts from the front" :
                            "bone parts from the patient's left",
                    C::text);
        const std::string left  = front ? "right" : "face";
        const std::string right = front ? "left" : "back";
        const long        mid_y = margin_top + height / 2 - 7;
        raster.text(margin_left - 8 - Raster::text_width(left),
                    mid_y,
                    left,
                    C::text);
        raster.text(margin_left + width + 8, mid_y, right, C::text);
        raster.text(margin_left + width / 2 - 8,
                    margin_top - 20,
                    "up",
                    C::text);
        raster.text(margin_left + width / 2 - 16,
                    margin_top + height + 4,
                    "down",
                    C::text);
        const double length = 50.;
        const long   y = margin_top + height + 32, x0 = margin_left;
        const long   x1 = x0 + std::lround(length * project.pixels_per_mm);
        raster.fill_rectangle(x0, y, x1, y + 4, C::text);
        raster.text(x1 + 10, y - 5, "50 mm", C::text);

        std::vector<std::pair<Colour, std::string>> entries;
        for (unsigned int s = 0; s < segments.size(); ++s)
          entries.emplace_back(C::part(s), segments[s].name);
        if (segments.empty())
          entries.emplace_back(C::bone, "bone (not split)");
        else
          {
            entries.emplace_back(C::bone, "no segment");
            entries.emplace_back(C::detached, "detached (cut margin)");
          }
        long ly = margin_top;
        for (const auto &[colour, name] : entries)
          {
            const long lx = margin_left + width + 60;
            raster.fill_rectangle(lx, ly + 2, lx + 10, ly + 12, colour);
            raster.text(lx + 18, ly, name, C::text, 1, false);
            ly += 20;
          }
      }
    } // namespace

    TriangleSurface
    bone_surface(const LabelVolume &parts)
    {
      Volume<float> mask;
      mask.reinit_like(parts);
      for (std::size_t v = 0; v < parts.n_voxels(); ++v)
        mask.values[v] = parts.values[v] != 0;
      // Blurred by (1, 2, 1) / 4 along each axis: the surface of a mask of
      // voxels is a staircase, which shading shows as terraces. A bone one
      // voxel thin keeps 0.5 at its centre: the level 0.4 keeps it.
      const long         stride[3] = {1,
                                      long(mask.size[0]),
                                      long(mask.size[0] * mask.size[1])};
      std::vector<float> blurred(mask.values.size());
      for (unsigned int pass = 0; pass < 3; ++pass)
        {
          const unsigned int d = pass;
          for (std::size_t v = 0; v < mask.values.size(); ++v)
            {
              const std::size_t i =
                (v / stride[d]) % mask.size[d]; // index along axis d
              const float low =
                i > 0 ? mask.values[v - stride[d]] : mask.values[v];
              const float high = i + 1 < mask.size[d] ?
                                   mask.values[v + stride[d]] :
                                   mask.values[v];
              blurred[v] = 0.25f * low + 0.5f * mask.values[v] + 0.25f * high;
            }
          mask.values.swap(blurred);
        }
      return iso_surface(mask, 0.4, false, 20);
    }

    RgbImage
    bone_view(const LabelVolume              &parts,
              const TriangleSurface          &surface,
              const std::vector<SegmentSeed> &segments,
              const BoneViewSide              side)
    {
      const bool split = !segments.empty();
      // The CT's extent at the slices' scale.
      Projection  project{side, VolumeBounds::of(parts), 0.};
      const auto &b       = project.bounds;
      double      largest = 0.;
      for (unsigned int d = 0; d < 3; ++d)
        largest = std::max(largest, b.upper[d] - b.lower[d]);
      project.pixels_per_mm = SliceGeometry::image_pixels / largest;
      const unsigned int h  = side == BoneViewSide::front ? 0 : 1;
      const long         width =
        std::lround((b.upper[h] - b.lower[h]) * project.pixels_per_mm);
      const long height =
        std::lround((b.upper[2] - b.lower[2]) * project.pixels_per_mm);

      RgbImage image(margin_left + width + 60 + 190,
                     std::max(margin_top + height + 60, 300L));
      Raster   raster(image);
      raster.fill_rectangle(0, 0, image.width, image.height, C::background);
      raster.fill_rectangle(margin_left,
                            margin_top,
                            margin_left + width - 1,
                            margin_top + height - 1,
                            {{0, 0, 0}});
      std::vector<double> depth(std::size_t(image.width) * image.height,
                                std::numeric_limits<double>::infinity());
      // Each vertex's normal: the sum of its triangles' area normals.
      std::vector<Vec3> normal(surface.points.size(), Vec3{{0., 0., 0.}});
      const auto        corners = [&](const std::array<unsigned int, 3> &t) {
        return std::array<Vec3, 3>{
          {surface.points[t[0]], surface.points[t[1]], surface.points[t[2]]}};
      };
      for (const auto &t : surface.triangles)
        {
          const Vec3 n = area_normal(corners(t));
          for (const auto i : t)
            for (unsigned int d = 0; d < 3; ++d)
              normal[i][d] += n[d];
        }
      const unsigned int view_axis = side == BoneViewSide::front ? 1 : 0;
      for (const auto &t : surface.triangles)
        {
          const auto            corner = corners(t);
          std::array<double, 3> lambert;
          Vec3                  centre{{0., 0., 0.}};
          for (unsigned int k = 0; k < 3; ++k)
            {
              const Vec3  &n = normal[t[k]];
              const double norm =
                std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
              lambert[k] = norm > 0. ? std::abs(n[view_axis]) / norm : 0.;
              for (unsigned int d = 0; d < 3; ++d)
                centre[d] += corner[k][d] / 3.;
            }
          draw_triangle(raster,
                        depth,
                        image.width,
                        corner,
                        lambert,
                        project,
                        colour_of(part_at(parts, centre), split));
        }
      draw_frame(raster, project, width, height, segments);
      return image;
    }
  } // namespace Patient
} // namespace softface

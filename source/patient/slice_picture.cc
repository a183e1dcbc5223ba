// The preview's slice pictures (slice_picture.h): a CT slice through a
// point, with what the scene says about it drawn where it lies, so that a
// user sees a misplaced seed point or cut before a run fails on it.

#include <softface/patient/preview_colours.h>
#include <softface/patient/raster.h>
#include <softface/patient/slice_picture.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    template <typename T>
    VolumeBounds
    VolumeBounds::of(const Volume<T> &volume)
    {
      // The corners of the voxels' extent, through the direction cosines.
      VolumeBounds b;
      b.lower.fill(std::numeric_limits<double>::infinity());
      b.upper.fill(-std::numeric_limits<double>::infinity());
      for (unsigned int c = 0; c < 8; ++c)
        {
          const Vec3 x = volume.point((c & 1) ? volume.size[0] - 0.5 : -0.5,
                                      (c & 2) ? volume.size[1] - 0.5 : -0.5,
                                      (c & 4) ? volume.size[2] - 0.5 : -0.5);
          for (unsigned int d = 0; d < 3; ++d)
            {
              b.lower[d] = std::min(b.lower[d], x[d]);
              b.upper[d] = std::max(b.upper[d], x[d]);
            }
        }
      return b;
    }

    template VolumeBounds
    VolumeBounds::of(const Volume<std::int16_t> &);
    template VolumeBounds
    VolumeBounds::of(const Volume<std::uint8_t> &);

    SliceGeometry::SliceGeometry(const Orientation   orientation,
                                 const VolumeBounds &bounds,
                                 const Vec3         &point)
        : orientation(orientation)
        , normal_axis(orientation == axial ? 2 :
                                             (orientation == coronal ? 1 : 0))
        , h_axis(orientation == sagittal ? 1 : 0)
        , v_axis(orientation == axial ? 1 : 2)
        , v_up(orientation != axial)
        , point(point)
        , bounds(bounds)
    {
      double largest = 0.;
      for (unsigned int d = 0; d < 3; ++d)
        largest = std::max(largest, bounds.upper[d] - bounds.lower[d]);
      pixels_per_mm = image_pixels / largest;
      width  = std::lround((bounds.upper[h_axis] - bounds.lower[h_axis]) *
                          pixels_per_mm);
      height = std::lround((bounds.upper[v_axis] - bounds.lower[v_axis]) *
                           pixels_per_mm);
    }

    std::array<double, 2>
    SliceGeometry::pixel(const Vec3 &x) const
    {
      const double h = (x[h_axis] - bounds.lower[h_axis]) * pixels_per_mm;
      const double v = v_up ?
                         (bounds.upper[v_axis] - x[v_axis]) * pixels_per_mm :
                         (x[v_axis] - bounds.lower[v_axis]) * pixels_per_mm;
      return {{margin_left + h - 0.5, margin_top + v - 0.5}};
    }

    Vec3
    SliceGeometry::position(const double px, const double py) const
    {
      const double h = (px - margin_left + 0.5) / pixels_per_mm;
      const double v = (py - margin_top + 0.5) / pixels_per_mm;
      Vec3         x = point;
      x[h_axis]      = bounds.lower[h_axis] + h;
      x[v_axis] = v_up ? bounds.upper[v_axis] - v : bounds.lower[v_axis] + v;
      return x;
    }

    namespace
    {
      namespace C = PreviewColours;

      std::string
      fixed(const double x, const int digits = 1)
      {
        std::ostringstream s;
        s << std::fixed << std::setprecision(digits) << x;
        return s.str();
      }

      // The grey of a CT value: a window wide enough for soft tissue and
      // bone at once.
      std::uint8_t
      grey(const double hu)
      {
        const double low = -700., high = 1300.;
        return static_cast<std::uint8_t>(
          std::lround(255. * std::clamp((hu - low) / (high - low), 0., 1.)));
      }

      // The tint of a voxel's label and part (alpha 0: none).
      std::pair<Colour, double>
      tint(const SliceContent &content, const std::size_t v)
      {
        switch (content.labels.values[v])
          {
            case skin_tissue:
              return {C::skin, 0.35};
            case fat_tissue:
              return {C::fat, 0.3};
            case muscle_tissue:
              return {C::muscle, 0.3};
            case internal_tissue:
              return {C::internal, 0.2};
            case bone_tissue:
              {
                if (content.parts == nullptr)
                  return {C::bone, 0.45};
                const auto p = content.parts->values[v];
                if (is_detached(p))
                  return {C::detached, 0.5};
                return {p == 0 ? C::bone : C::part(p - 1), 0.5};
              }
            default:
              return {C::bone, 0.};
          }
      }

      // The CT, tinted by the labels. Returns each image pixel's bone
      // part value (-2: no bone; -1: bone, no parts made), for the names.
      std::vector<int>
      draw_ct(Raster              &raster,
              const SliceContent  &content,
              const SliceGeometry &g)
      {
        std::vector<int> part_of_pixel(g.width * g.height, -2);
        for (long r = 0; r < g.height; ++r)
          for (long c = 0; c < g.width; ++c)
            {
              const long                 px = g.margin_left + c;
              const long                 py = g.margin_top + r;
              std::array<std::size_t, 3> ijk;
              if (!content.ct.nearest_voxel(g.position(px, py), ijk))
                {
                  raster.set(px, py, {{0, 0, 0}});
                  continue;
                }
              const std::size_t v = content.ct.index(ijk[0], ijk[1], ijk[2]);
              const auto        y = grey(content.ct.values[v]);
              raster.set(px, py, {{y, y, y}});
              const auto [colour, alpha] = tint(content, v);
              if (alpha > 0.)
                raster.blend(px, py, colour, alpha);
              if (content.labels.values[v] == bone_tissue)
                part_of_pixel[r * g.width + c] =
                  content.parts ? content.parts->values[v] : -1;
            }
        return part_of_pixel;
      }

      // A cut where its surface crosses the slice: the pixels whose
      // centre lies within about a pixel of it, measured along the slice
      // (the distance's change to the neighbouring pixels gives its slope),
      // so that a plane at a slant is as thin as one across. Beyond the
      // cut's box it is drawn dimmer and dashed.
      void
      draw_cut(Raster              &raster,
               const Cut           &cut,
               const SliceGeometry &g,
               const Colour        &inside,
               const Colour        &outside)
      {
        const double mm = 1. / g.pixels_per_mm;
        for (long r = 0; r < g.height; ++r)
          for (long c = 0; c < g.width; ++c)
            {
              const long   px = g.margin_left + c, py = g.margin_top + r;
              const Vec3   x = g.position(px, py);
              const double d = cut.surface_distance(x);
              if (d > 2. * mm)
                continue;
              double slope = 0.;
              for (const auto &[dx, dy] : {std::pair{1, 0},
                                           std::pair{-1, 0},
                                           std::pair{0, 1},
                                           std::pair{0, -1}})
                slope = std::max(slope,
                                 std::abs(cut.surface_distance(
                                            g.position(px + dx, py + dy)) -
                                          d) /
                                   mm);
              if (d >= 1.0 * mm * std::max(slope, 0.15))
                continue;
              if (cut.in_box(x))
                raster.set(px, py, inside);
              else if (((c + r) / 6) % 2 == 0)
                raster.set(px, py, outside);
            }
      }

      // The outline of an axis-aligned box where it meets the slice: the
      // edges that lie in the CT's extent, drawn as far as the CT goes.
      void
      draw_box(Raster              &raster,
               const Vec3          &lower,
               const Vec3          &upper,
               const SliceGeometry &g,
               const Colour        &colour,
               const unsigned int   dash)
      {
        const unsigned int n = g.normal_axis, h = g.h_axis, v = g.v_axis;
        if (g.point[n] < lower[n] || g.point[n] > upper[n])
          return;
        const auto &b     = g.bounds;
        const auto  clamp = [&](const double x, const unsigned int d) {
          return std::clamp(x, b.lower[d], b.upper[d]);
        };
        Vec3 a = g.point, c = g.point;
        a[h] = clamp(lower[h], h), c[h] = clamp(upper[h], h);
        a[v] = clamp(lower[v], v), c[v] = clamp(upper[v], v);
        if (a[h] >= c[h] || a[v] >= c[v])
          return;
        const auto p = g.pixel(a), q = g.pixel(c);
        // Each edge of the box (not the CT's edge it was clamped to).
        if (lower[h] >= b.lower[h])
          raster.line(p[0], p[1], p[0], q[1], colour, 2, dash);
        if (upper[h] <= b.upper[h])
          raster.line(q[0], p[1], q[0], q[1], colour, 2, dash);
        if (lower[v] >= b.lower[v])
          raster.line(p[0], p[1], q[0], p[1], colour, 2, dash);
        if (upper[v] <= b.upper[v])
          raster.line(p[0], q[1], q[0], q[1], colour, 2, dash);
      }

      // Is the seed point @p seed drawn on the slice: near it, and inside
      // its image?
      bool
      seed_drawn(const Vec3 &seed, const SliceGeometry &g)
      {
        if (std::abs(seed[g.normal_axis] - g.point[g.normal_axis]) >
            seed_drawing_distance)
          return false;
        const auto p = g.pixel(seed);
        return p[0] >= g.margin_left && p[1] >= g.margin_top &&
               p[0] < g.margin_left + g.width && p[1] < g.margin_top + g.height;
      }

      // Each seed point near the slice: a cross and its segment's name.
      void
      draw_seeds(Raster              &raster,
                 const SliceContent  &content,
                 const SliceGeometry &g)
      {
        for (const auto &seed : content.segments)
          if (seed_drawn(seed.point, g))
            {
              const auto p = g.pixel(seed.point);
              raster.cross(p[0], p[1], 9, C::seed);
              raster.text(std::lround(p[0]) + 8,
                          std::lround(p[1]) - 20,
                          seed.name,
                          C::text);
            }
      }

      // Each bone part's segment (or "no segment") on the part: at its
      // pixel nearest to the part's centre in the slice. A part whose seed
      // point is drawn is named there already; the thin detached bone
      // along the cuts is left to the legend.
      void
      name_parts(Raster                 &raster,
                 const SliceContent     &content,
                 const SliceGeometry    &g,
                 const std::vector<int> &part_of_pixel)
      {
        std::map<int, std::array<double, 3>> sums;
        for (long i = 0; i < long(part_of_pixel.size()); ++i)
          if (part_of_pixel[i] >= 0)
            {
              auto &s = sums[part_of_pixel[i]];
              s[0] += 1., s[1] += i % g.width, s[2] += i / g.width;
            }
        for (const auto &[part, s] : sums)
          {
            if (s[0] < 40. || is_detached(part) ||
                (part > 0 && seed_drawn(content.segments[part - 1].point, g)))
              continue;
            const double cx = s[1] / s[0], cy = s[2] / s[0];
            long         best   = 0;
            double       best_d = std::numeric_limits<double>::infinity();
            for (long i = 0; i < long(part_of_pixel.size()); ++i)
              if (part_of_pixel[i] == part)
                {
                  const double d =
                    std::hypot(i % g.width - cx, i / g.width - cy);
                  if (d < best_d)
                    best_d = d, best = i;
                }
            const std::string name =
              part == 0 ? "no segment" : content.segments[part - 1].name;
            const Colour colour = part == 0 ? C::bone : C::part(part - 1);
            raster.text(g.margin_left + best % g.width -
                          Raster::text_width(name) / 2,
                        g.margin_top + best / g.width -
                          Raster::text_height() / 2,
                        name,
                        colour);
          }
      }

      // The title, the orientation on the four sides and a scale bar.
      void
      draw_frame(Raster &raster, const SliceGeometry &g)
      {
        static const char *names[3] = {"axial", "coronal", "sagittal"};
        static const char *axes[3]  = {"x", "y", "z"};
        const unsigned int n        = g.normal_axis;
        raster.text(g.margin_left,
                    10,
                    std::string(names[g.orientation]) + " slice " + axes[n] +
                      " = " + fixed(g.point[n]) + " mm through (" +
                      fixed(g.point[0]) + ", " + fixed(g.point[1]) + ", " +
                      fixed(g.point[2]) + ")",
                    C::text);
        // What lies towards each side: LPS, the face towards -y.
        const char       *low[3]  = {"right", "face", "down"};
        const char       *high[3] = {"left", "back", "up"};
        const std::string left = low[g.h_axis], right = high[g.h_axis];
        const std::string top    = g.v_up ? high[g.v_axis] : low[g.v_axis];
        const std::string bottom = g.v_up ? low[g.v_axis] : high[g.v_axis];
        const long        mid_y  = g.margin_top + g.height / 2 - 7;
        const long        mid_x  = g.margin_left + g.width / 2;
        raster.text(g.margin_left - 8 - Raster::text_width(left),
                    mid_y,
                    left,
                    C::text);
        raster.text(g.margin_left + g.width + 8, mid_y, right, C::text);
        raster.text(mid_x - Raster::text_width(top) / 2,
                    g.margin_top - 20,
                    top,
                    C::text);
        raster.text(mid_x - Raster::text_width(bottom) / 2,
                    g.margin_top + g.height + 4,
                    bottom,
                    C::text);
        // A scale bar of a round length near a fifth of the image.
        double length = 10.;
        for (const double l : {20., 50., 100.})
          if (l * g.pixels_per_mm <= 0.25 * g.width)
            length = l;
        const long y  = g.margin_top + g.height + 32;
        const long x0 = g.margin_left;
        const long x1 = x0 + std::lround(length * g.pixels_per_mm);
        raster.fill_rectangle(x0, y, x1, y + 4, C::text);
        raster.fill_rectangle(x0, y - 4, x0 + 1, y + 8, C::text);
        raster.fill_rectangle(x1 - 1, y - 4, x1, y + 8, C::text);
        raster.text(x1 + 10, y - 5, fixed(length, 0) + " mm", C::text);
      }

      // What each colour means, in the right margin.
      long
      draw_legend(Raster &raster, const SliceContent &content, const long x)
      {
        std::vector<std::pair<Colour, std::string>> entries;
        if (content.parts != nullptr)
          {
            for (unsigned int s = 0; s < content.segments.size(); ++s)
              entries.emplace_back(C::part(s), content.segments[s].name);
            entries.emplace_back(C::bone, "no segment");
            entries.emplace_back(C::detached, "detached (cut margin)");
          }
        else
          entries.emplace_back(C::bone, "bone (not split)");
        entries.emplace_back(C::skin, "skin");
        entries.emplace_back(C::fat, "fat");
        entries.emplace_back(C::muscle, "muscle");
        entries.emplace_back(C::internal, "internal soft tissue");
        entries.emplace_back(C::cut, "cut");
        entries.emplace_back(C::cut_outside_box, "cut beyond its box");
        entries.emplace_back(C::cut_box, "cut's box");
        entries.emplace_back(C::region, "region of interest");
        entries.emplace_back(C::seed, "seed point");
        long y = SliceGeometry::margin_top;
        for (const auto &[colour, name] : entries)
          {
            raster.fill_rectangle(x, y + 2, x + 10, y + 12, colour);
            raster.text(x + 18, y, name, C::text, 1, false);
            y += 20;
          }
        raster.text(x, y + 6, "seed points drawn", C::text, 1, false);
        raster.text(x,
                    y + 24,
                    "within " + fixed(seed_drawing_distance, 0) +
                      " mm of the slice",
                    C::text,
                    1,
                    false);
        return y + 44;
      }
    } // namespace

    RgbImage
    slice_picture(const SliceContent &content, const SliceGeometry &g)
    {
      const long legend_x = g.margin_left + g.width + 60;
      const long legend_w = 215;
      RgbImage   image(legend_x + legend_w,
                     std::max(g.margin_top + g.height + 60, 400L));
      Raster     raster(image);
      raster.fill_rectangle(0, 0, image.width, image.height, C::background);
      const long legend_end = draw_legend(raster, content, legend_x);
      if (legend_end > long(image.height))
        {
          // A flat slice: a taller picture for the legend.
          image = RgbImage(image.width, legend_end);
          raster.fill_rectangle(0, 0, image.width, image.height, C::background);
          draw_legend(raster, content, legend_x);
        }
      const auto part_of_pixel = draw_ct(raster, content, g);
      draw_box(
        raster, content.roi.box_min, content.roi.box_max, g, C::region, 8);
      for (const auto &[point, normal] : content.roi.planes)
        {
          Cut plane;
          plane.point = point, plane.normal = normal;
          const double n =
            std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] +
                      normal[2] * normal[2]);
          for (auto &x : plane.normal)
            x /= n;
          draw_cut(raster, plane, g, C::region, C::region);
        }
      for (const auto &cut : content.osteotomy.cuts)
        draw_box(raster, cut.box_min, cut.box_max, g, C::cut_box, 6);
      for (const auto &cut : content.osteotomy.cuts)
        draw_cut(raster, cut, g, C::cut, C::cut_outside_box);
      name_parts(raster, content, g, part_of_pixel);
      draw_seeds(raster, content, g);
      draw_frame(raster, g);
      return image;
    }
  } // namespace Patient
} // namespace softface

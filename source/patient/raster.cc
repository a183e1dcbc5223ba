// Drawing on the preview's RGB pictures (raster.h): a handful of primitives
// and a bitmap font, so that the preview needs neither a display nor a
// graphics library, only a PNG writer.

#include <softface/patient/raster.h>

#include <algorithm>
#include <cmath>

namespace softface
{
  namespace Patient
  {
    namespace
    {
#include "bitmap_font_glyphs.h"

      constexpr long glyph_width  = 8;
      constexpr long glyph_height = 14;
    } // namespace

    void
    Raster::set(const long x, const long y, const Colour &c)
    {
      if (!inside(x, y))
        return;
      const std::size_t p = 3 * (std::size_t(y) * image.width + x);
      for (unsigned int k = 0; k < 3; ++k)
        image.rgb[p + k] = c[k];
    }

    Colour
    Raster::get(const long x, const long y) const
    {
      if (!inside(x, y))
        return {{0, 0, 0}};
      const std::size_t p = 3 * (std::size_t(y) * image.width + x);
      return {{image.rgb[p], image.rgb[p + 1], image.rgb[p + 2]}};
    }

    void
    Raster::blend(const long    x,
                  const long    y,
                  const Colour &c,
                  const double  alpha)
    {
      const Colour old = get(x, y);
      Colour       mixed;
      for (unsigned int k = 0; k < 3; ++k)
        mixed[k] = static_cast<std::uint8_t>(
          std::lround((1. - alpha) * old[k] + alpha * c[k]));
      set(x, y, mixed);
    }

    void
    Raster::fill_rectangle(long x0, long y0, long x1, long y1, const Colour &c)
    {
      if (x0 > x1)
        std::swap(x0, x1);
      if (y0 > y1)
        std::swap(y0, y1);
      x0 = std::max(x0, 0L), y0 = std::max(y0, 0L);
      x1 = std::min(x1, long(image.width) - 1);
      y1 = std::min(y1, long(image.height) - 1);
      for (long y = y0; y <= y1; ++y)
        for (long x = x0; x <= x1; ++x)
          set(x, y, c);
    }

    void
    Raster::line(double             x0,
                 double             y0,
                 double             x1,
                 double             y1,
                 const Colour      &c,
                 const unsigned int width,
                 const unsigned int dash)
    {
      // Far-away ends (a box of 1e9 mm) are pulled in first, so that the
      // steps below stay few: a line is clipped to a margin around the
      // picture along its own direction.
      const double length = std::hypot(x1 - x0, y1 - y0);
      if (!(length > 0.) || !std::isfinite(length))
        return;
      const double ux = (x1 - x0) / length, uy = (y1 - y0) / length;
      double       t0 = 0., t1 = length;
      const double lo[2] = {-10., -10.};
      const double hi[2] = {image.width + 10., image.height + 10.};
      const double p[2] = {x0, y0}, u[2] = {ux, uy};
      for (unsigned int d = 0; d < 2; ++d)
        {
          if (std::abs(u[d]) < 1e-12)
            {
              if (p[d] < lo[d] || p[d] > hi[d])
                return;
              continue;
            }
          double a = (lo[d] - p[d]) / u[d], b = (hi[d] - p[d]) / u[d];
          if (a > b)
            std::swap(a, b);
          t0 = std::max(t0, a), t1 = std::min(t1, b);
        }
      if (t0 > t1)
        return;
      // Steps of a third of a pixel, a square of width pixels at each.
      const long   half = long(width) / 2;
      const double step = 1. / 3.;
      for (double t = t0; t <= t1; t += step)
        {
          if (dash > 0 && long(std::floor(t / dash)) % 2 == 1)
            continue;
          const long x = std::lround(x0 + t * ux - 0.5 * (width % 2 == 0));
          const long y = std::lround(y0 + t * uy - 0.5 * (width % 2 == 0));
          for (long dy = -half; dy < long(width) - half; ++dy)
            for (long dx = -half; dx < long(width) - half; ++dx)
              set(x + dx, y + dy, c);
        }
    }

    void
    Raster::rectangle(const double       x0,
                      const double       y0,
                      const double       x1,
                      const double       y1,
                      const Colour      &c,
                      const unsigned int width,
                      const unsigned int dash)
    {
      line(x0, y0, x1, y0, c, width, dash);
      line(x1, y0, x1, y1, c, width, dash);
      line(x1, y1, x0, y1, c, width, dash);
      line(x0, y1, x0, y0, c, width, dash);
    }

    void
    Raster::cross(const double  x,
                  const double  y,
                  const int     arm,
                  const Colour &c)
    {
      line(x - arm, y, x + arm, y, c, 3);
      line(x, y - arm, x, y + arm, c, 3);
    }

    long
    Raster::text_width(const std::string &text, const unsigned int scale)
    {
      return long(text.size()) * glyph_width * scale;
    }

    long
    Raster::text_height(const unsigned int scale)
    {
      return glyph_height * scale;
    }

    void
    Raster::text(const long         x,
                 const long         y,
                 const std::string &text,
                 const Colour      &c,
                 const unsigned int scale,
                 const bool         outline)
    {
      // Outline first (every lit font pixel's neighbours in black), then
      // the glyphs over it.
      for (const int pass : {0, 1})
        {
          if (pass == 0 && !outline)
            continue;
          for (std::size_t i = 0; i < text.size(); ++i)
            {
              const int   code = static_cast<unsigned char>(text[i]);
              const auto &rows =
                glyph_rows[(code >= 32 && code <= 126) ? code - 32 : '?' - 32];
              const long left = x + long(i) * glyph_width * scale;
              for (long r = 0; r < glyph_height; ++r)
                for (long b = 0; b < glyph_width; ++b)
                  if (rows[r] & (0x80 >> b))
                    for (long sy = 0; sy < long(scale); ++sy)
                      for (long sx = 0; sx < long(scale); ++sx)
                        {
                          const long px = left + b * scale + sx,
                                     py = y + r * scale + sy;
                          if (pass == 1)
                            set(px, py, c);
                          else
                            for (long dy = -1; dy <= 1; ++dy)
                              for (long dx = -1; dx <= 1; ++dx)
                                set(px + dx, py + dy, {{0, 0, 0}});
                        }
            }
        }
    }
  } // namespace Patient
} // namespace softface

#ifndef softface_patient_raster_h
#define softface_patient_raster_h

#include <softface/patient/png_io.h>

#include <array>
#include <cstdint>
#include <string>

namespace softface
{
  namespace Patient
  {
    /// An RGB colour.
    using Colour = std::array<std::uint8_t, 3>;

    /**
     * Drawing on an RgbImage for the preview's pictures: pixels, lines,
     * rectangles, crosses and text in a small bitmap font (8 x 14 pixels a
     * character, ASCII 32-126, bitmap_font_glyphs.h), all clipped to the
     * picture. Coordinates are pixels, x to the right and y down from the
     * top left corner.
     */
    class Raster
    {
    public:
      explicit Raster(RgbImage &image)
          : image(image)
      {}

      /// Is (x, y) a pixel of the picture?
      bool
      inside(const long x, const long y) const
      {
        return x >= 0 && y >= 0 && x < long(image.width) &&
               y < long(image.height);
      }

      void
      set(const long x, const long y, const Colour &c);

      Colour
      get(const long x, const long y) const;

      /// @p c laid over the pixel with opacity @p alpha (0 to 1).
      void
      blend(const long x, const long y, const Colour &c, const double alpha);

      void
      fill_rectangle(long x0, long y0, long x1, long y1, const Colour &c);

      /// A line @p width pixels wide; @p dash > 0 draws every other run of
      /// @p dash pixels.
      void
      line(double             x0,
           double             y0,
           double             x1,
           double             y1,
           const Colour      &c,
           const unsigned int width = 1,
           const unsigned int dash  = 0);

      /// The outline of the rectangle with corners (x0, y0) and (x1, y1).
      void
      rectangle(const double       x0,
                const double       y0,
                const double       x1,
                const double       y1,
                const Colour      &c,
                const unsigned int width = 1,
                const unsigned int dash  = 0);

      /// A cross of arms @p arm pixels long centred on (x, y).
      void
      cross(const double x, const double y, const int arm, const Colour &c);

      /// @p text with its top left corner at (x, y), each font pixel drawn
      /// as @p scale x @p scale pixels; with @p outline, a one-pixel black
      /// rim keeps it legible on any background.
      void
      text(const long         x,
           const long         y,
           const std::string &text,
           const Colour      &c,
           const unsigned int scale   = 1,
           const bool         outline = true);

      /// Pixel width and height of @p text at @p scale.
      static long
      text_width(const std::string &text, const unsigned int scale = 1);
      static long
      text_height(const unsigned int scale = 1);

    private:
      RgbImage &image;
    };
  } // namespace Patient
} // namespace softface

#endif

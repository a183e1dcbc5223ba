#ifndef softface_patient_png_io_h
#define softface_patient_png_io_h

#include <cstdint>
#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// An 8-bit RGB picture, rows from the top, pixels left to right.
    struct RgbImage
    {
      unsigned int              width  = 0;
      unsigned int              height = 0;
      std::vector<std::uint8_t> rgb; ///< 3 * width * height

      RgbImage() = default;
      RgbImage(const unsigned int w, const unsigned int h)
          : width(w)
          , height(h)
          , rgb(3 * std::size_t(w) * h, 0)
      {}
    };

    /// Written as PNG through ITK's PNGImageIO; an Error names the file.
    void
    write_png(const RgbImage &image, const std::string &filename);

    /// An RGB PNG file read back (the preview's test); an Error names it.
    RgbImage
    read_png(const std::string &filename);
  } // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_preview_colours_h
#define softface_patient_preview_colours_h

#include <softface/patient/raster.h>

namespace softface
{
  namespace Patient
  {
    /**
     * The colours of the preview's pictures. The marks (seed points, cuts,
     * boxes, region of interest) have pure colours that no tinted CT pixel
     * takes (a tint lays a colour over grey at half opacity or less), so
     * that a reader, or a test, tells them from the image.
     */
    namespace PreviewColours
    {
      constexpr Colour seed{{255, 0, 255}};
      constexpr Colour cut{{255, 255, 0}};
      /// The cut's plane beyond its box, where it cuts nothing.
      constexpr Colour cut_outside_box{{150, 150, 0}};
      constexpr Colour cut_box{{255, 140, 0}};
      constexpr Colour region{{0, 230, 0}};
      constexpr Colour text{{255, 255, 255}};
      constexpr Colour background{{40, 40, 40}};
      constexpr Colour skin{{255, 170, 140}};
      constexpr Colour fat{{255, 225, 110}};
      constexpr Colour muscle{{225, 70, 70}};
      constexpr Colour internal{{150, 150, 210}};
      /// Bone when there are no parts, or bone no segment claims.
      constexpr Colour bone{{235, 225, 195}};
      constexpr Colour detached{{160, 160, 160}};

      /// The colour of bone part @p s (0-based: segment s).
      inline Colour
      part(const unsigned int s)
      {
        constexpr Colour palette[10] = {{{70, 130, 255}},
                                        {{230, 60, 60}},
                                        {{40, 200, 200}},
                                        {{160, 90, 230}},
                                        {{60, 200, 90}},
                                        {{240, 150, 60}},
                                        {{230, 110, 180}},
                                        {{150, 190, 60}},
                                        {{120, 110, 255}},
                                        {{200, 170, 120}}};
        return palette[s % 10];
      }
    } // namespace PreviewColours
  }   // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_slice_picture_h
#define softface_patient_slice_picture_h

#include <softface/patient/osteotomy.h>
#include <softface/patient/png_io.h>
#include <softface/patient/segmentation.h>
#include <softface/patient/tetrahedral_mesh.h>
#include <softface/patient/volume.h>

#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// The axis-aligned box a volume's voxels cover (their corners), mm.
    struct VolumeBounds
    {
      Vec3 lower, upper;

      template <typename T>
      static VolumeBounds
      of(const Volume<T> &volume);

      bool
      contains(const Vec3 &x) const
      {
        for (unsigned int d = 0; d < 3; ++d)
          if (!(x[d] >= lower[d] && x[d] <= upper[d]))
            return false;
        return true;
      }
    };

    /**
     * Where a slice picture puts the patient frame (LPS: x to the patient's
     * left, y posterior, z superior). The image of the slice starts at
     * pixel (margin_left, margin_top) of the picture; the CT's largest
     * extent spans image_pixels pixels, the same scale in the three views.
     * Axial (z fixed): x to the right, y down (the face at the top).
     * Coronal (y fixed): x to the right, z up. Sagittal (x fixed): y to the
     * right (the face on the left), z up. So the patient's right is on the
     * picture's left, as radiologists show it.
     */
    struct SliceGeometry
    {
      enum Orientation
      {
        axial,
        coronal,
        sagittal
      };
      static constexpr long   margin_left  = 80;
      static constexpr long   margin_top   = 60;
      static constexpr double image_pixels = 600.;

      SliceGeometry(const Orientation   orientation,
                    const VolumeBounds &bounds,
                    const Vec3         &point);

      /// The picture's pixel (x, y) of the position @p x (continuous:
      /// pixel centres at integers); its distance from the slice is lost.
      std::array<double, 2>
      pixel(const Vec3 &x) const;
      /// The position of the picture's pixel (x, y), in the slice.
      Vec3
      position(const double px, const double py) const;

      Orientation  orientation;
      unsigned int normal_axis, h_axis, v_axis; ///< 0 x, 1 y, 2 z
      bool         v_up; ///< v grows upwards (coronal, sagittal)
      Vec3         point;
      VolumeBounds bounds;
      double       pixels_per_mm;
      long         width, height; ///< of the slice's image, pixels
    };

    /// What the slice pictures show: the CT, its labels and (if made) the
    /// bone parts, with the scene's cuts, seeds and region of interest.
    struct SliceContent
    {
      const CTVolume                 &ct;
      const LabelVolume              &labels;
      const LabelVolume              *parts; ///< nullptr: not made
      const std::vector<SegmentSeed> &segments;
      const OsteotomyParameters      &osteotomy;
      const RegionOfInterest         &roi;
    };

    /// mm: a seed point this close to a slice is drawn on it.
    constexpr double seed_drawing_distance = 5.;

    /**
     * The picture of one slice through @p geometry.point: the CT in grey
     * (window -700 to 1300 HU, soft tissue and bone both visible), the
     * soft tissue's labels tinted, each bone part in its colour with its
     * segment's name, the cuts (where their surface crosses the slice;
     * dimmer beyond their box) and the outline of their boxes, each seed
     * point within seed_drawing_distance of the slice as a cross with its
     * segment's name, the region of interest's box, a scale bar, the
     * orientation on the four sides and a legend.
     */
    RgbImage
    slice_picture(const SliceContent &content, const SliceGeometry &geometry);
  } // namespace Patient
} // namespace softface

#endif

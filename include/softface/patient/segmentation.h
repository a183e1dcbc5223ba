#ifndef softface_patient_segmentation_h
#define softface_patient_segmentation_h

#include <softface/patient/volume.h>

#include <string>

namespace softface
{
  namespace Patient
  {
    /// Thresholds and sizes of the segmentation (plain data; the
    /// parameter file's subsection is declared by the pipeline).
    struct SegmentationParameters
    {
      double smoothing       = 0.5;   ///< mm, Gaussian before thresholds
      double body_threshold  = -480.; ///< HU between air and skin
      double bone_threshold  = 520.;  ///< HU between soft tissue and bone
      double fat_threshold   = -30.;  ///< HU between fat and muscle
      double skin_thickness  = 2.;    ///< mm under the body surface
      double min_bone_volume = 50.;   ///< mm^3; smaller bone pieces: noise
    };

    /**
     * The segmentation's labels. External soft tissue is what is connected
     * to the skin; soft tissue enclosed by bone (the brain) is internal and
     * not part of the facial model.
     */
    enum SegmentLabel : std::uint8_t
    {
      outside_body    = 0,
      skin_tissue     = 1,
      fat_tissue      = 2,
      muscle_tissue   = 3, ///< and every other external soft tissue
      bone_tissue     = 4,
      internal_tissue = 5
    };

    struct SegmentationResult
    {
      LabelVolume labels;
      /// The CT after the smoothing: what the surfaces are extracted from.
      Volume<float> smoothed;
      double        seconds = 0.;
    };

    /**
     * seed 3.1: the body (above the body threshold, holes filled, largest
     * piece), bone (above the bone threshold, small pieces dropped), and
     * the external soft tissue split into skin (within the skin thickness of
     * the body surface), fat (below the fat threshold) and muscle. Throws an
     * Error naming @p source and the threshold when one selects nothing.
     */
    SegmentationResult
    segment(const CTVolume               &ct,
            const SegmentationParameters &parameters,
            const std::string            &source);
  } // namespace Patient
} // namespace softface

#endif

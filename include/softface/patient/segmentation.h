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
      /// Thresholds taken from the scan's histogram ('auto') instead of
      /// the numbers above, so that a scan in other units than HU needs
      /// no translation.
      bool auto_body_threshold = false;
      bool auto_bone_threshold = false;
      bool auto_fat_threshold  = false;
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
      /// The thresholds used, in the CT's units: the parameters' numbers,
      /// or those chosen from the histogram where 'auto'.
      double body_threshold = 0.;
      double bone_threshold = 0.;
      double fat_threshold  = 0.;
      double seconds        = 0.;
    };

    /**
     * The thresholds of @p result as one line, each marked "(auto)" when
     * chosen from the histogram: "body -482.0 (auto), bone 520.0, fat -30.0".
     */
    std::string
    describe_thresholds(const SegmentationParameters &parameters,
                        const SegmentationResult     &result);

    /**
     * Mollemans et al. 2007, Sec. 3.1: the body (above the body threshold,
     * holes filled, largest piece), bone (above the bone threshold, small
     * pieces dropped), and the external soft tissue split into skin (within the
     * skin thickness of the body surface), fat (below the fat threshold) and
     * muscle. Throws an Error naming @p source and the threshold when one
     * selects nothing.
     *
     * An 'auto' threshold is chosen on the smoothed CT, each from the
     * voxels the threshold splits: the body's from every voxel, the bone's
     * from the body's, the fat's from the external soft tissue deeper than
     * the skin. Otsu's threshold (ITK) splits the voxels' histogram into
     * two classes, and the threshold is the midpoint of the two classes'
     * peaks (their modes; for bone 45 % of the way from soft tissue's peak
     * to bone's, since thin bone never reaches its peak), as the defaults
     * lie between the tissues' HU values; the peaks, unlike the classes'
     * means, do not move
     * with the partial-volume voxels of an interface or the long tails
     * (metal, dense teeth) of a real scan. A scan in other units (scale
     * and offset from HU) gets the same thresholds in its units.
     */
    SegmentationResult
    segment(const CTVolume               &ct,
            const SegmentationParameters &parameters,
            const std::string            &source);
  } // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_bone_view_h
#define softface_patient_bone_view_h

#include <softface/patient/osteotomy.h>
#include <softface/patient/png_io.h>
#include <softface/patient/surface.h>
#include <softface/patient/volume.h>

#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// From where the bone parts are seen.
    enum class BoneViewSide
    {
      front, ///< from -y: the patient's right on the picture's left
      left   ///< from the patient's left (+x): the face on the left
    };

    /// The surface bone_view() draws: the iso-surface of the bone of
    /// @p parts (every value but 0), its voxel steps smoothed a little.
    TriangleSurface
    bone_surface(const LabelVolume &parts);

    /**
     * The bone seen from @p side, each part in its colour: @p surface
     * (bone_surface()), each triangle coloured by the part of @p parts
     * around it (values as split_bone() gives them: s + 1 for segment s,
     * plus detached_flag where detached; @p parts may also be a mere bone mask
     * of value 1 with
     * @p segments empty: bone not split), drawn orthographically into a
     * z-buffer with Lambert shading by a light from the viewer, a scale
     * bar, the orientation and a legend. No display or graphics library is
     * needed.
     */
    RgbImage
    bone_view(const LabelVolume              &parts,
              const TriangleSurface          &surface,
              const std::vector<SegmentSeed> &segments,
              const BoneViewSide              side);
  } // namespace Patient
} // namespace softface

#endif

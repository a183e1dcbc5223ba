#ifndef softface_patient_preview_h
#define softface_patient_preview_h

#include <softface/patient/pipeline.h>

#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * 'softface preview': the patient stages up to the bone parts (the CT
     * and the segmentation reused when their stamps hold; the bone parts
     * split again, no mesh), then pictures into <work directory>/preview/:
     * axial, coronal and sagittal slices through the preview point with
     * the labels, bone parts, cuts, seed points and region of interest
     * drawn (slice_picture.h), and the bone parts seen from the front and
     * the side (bone_view.h). A split that fails (a seed in no bone, a part
     * of no segment) is reported and the pictures show what there is.
     * The files, the point and where each seed point and cut lies go to
     * @p out. Returns the exit code: 0, or 1 when the bone parts could not
     * be made.
     */
    int
    preview(const PatientParameters        &parameters,
            const std::vector<SegmentSeed> &segments,
            std::ostream                   &out);
  } // namespace Patient
} // namespace softface

#endif

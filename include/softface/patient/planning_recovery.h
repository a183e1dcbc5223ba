#ifndef softface_patient_planning_recovery_h
#define softface_patient_planning_recovery_h

#include <softface/patient/icp.h>
#include <softface/patient/surface.h>
#include <softface/patient/volume.h>

#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * The surface of each bone part of an osteotomy (marching cubes of the
     * voxels of segment s in @p parts, detached or not: the bone_parts volume
     * the mesh stage writes), in the patient frame.
     */
    std::vector<TriangleSurface>
    bone_part_surfaces(const LabelVolume &parts, const unsigned int n_segments);

    /**
     * A post-operative skull made from the pre-operative one: each part's
     * surface moved by its motion, all in one surface (for phantom
     * patients, whose post-operative CT does not exist).
     */
    TriangleSurface
    moved_skull(const std::vector<TriangleSurface> &parts,
                const std::vector<RigidTransform>  &motions);

    /**
     * Planning from a post-operative skull (Mollemans et al. 2007, Sec. 3.2):
     * each part's surface registered to @p post_operative by ICP from @p start
     * (a rough plan; the identity where there is none).
     */
    std::vector<IcpResult>
    recover_motions(const std::vector<TriangleSurface> &parts,
                    const TriangleSurface              &post_operative,
                    const std::vector<RigidTransform>  &start,
                    const IcpParameters                &parameters);

    /**
     * A Planning section of a scene (one "Motion <name>" per segment whose
     * motion moves any of its points by more than @p tolerance mm, as
     * rotation axis, angle, centre 0 and translation), with the fit of each
     * part as comments.
     */
    std::string
    planning_section(const std::vector<std::string>     &segment_names,
                     const std::vector<IcpResult>       &motions,
                     const std::vector<TriangleSurface> &parts,
                     const double                        tolerance = 0.01);
  } // namespace Patient
} // namespace softface

#endif

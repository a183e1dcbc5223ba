#ifndef softface_patient_pipeline_h
#define softface_patient_pipeline_h

#include <deal.II/base/parameter_handler.h>

#include <softface/patient/osteotomy.h>
#include <softface/patient/phantom.h>
#include <softface/patient/registration.h>
#include <softface/patient/segmentation.h>
#include <softface/patient/tetrahedral_mesh.h>

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * Subsection Scene/Patient/Registration, for 'softface register': the
     * post-operative CT, the surfaces made from it, and how it is registered
     * to the pre-operative CT (Mollemans et al. 2007, 3.5.1).
     */
    struct RegistrationStageParameters
    {
      /// Subsection "Registration" (the handler is inside "Patient").
      static void
      declare_parameters(dealii::ParameterHandler &prm);
      /// Relative files are taken from @p input_directory.
      void
      parse_parameters(dealii::ParameterHandler &prm,
                       const std::string        &input_directory);

      std::string              post_operative_ct; ///< empty: none
      std::vector<std::string> post_operative_surfaces;
      RegistrationParameters   registration;
    };

    /**
     * Everything of subsection Scene/Patient: where the CT comes from (a
     * file, a DICOM folder, or the phantom), the segmentation, the region of
     * interest, the tetrahedral mesh, the osteotomies, and the registration
     * of a post-operative CT.
     */
    struct PatientParameters
    {
      /// Subsection "Patient" (the handler is inside "Scene").
      static void
      declare_parameters(dealii::ParameterHandler       &prm,
                         const std::vector<std::string> &cut_names);
      /// The cut names of a parsed handler (inside "Scene").
      static std::vector<std::string>
      cut_names(dealii::ParameterHandler &prm);
      /// Relative files are taken from @p input_directory; an empty work
      /// directory becomes @p default_work_directory.
      void
      parse_parameters(dealii::ParameterHandler &prm,
                       const std::string        &input_directory,
                       const std::string        &default_work_directory);

      std::string                 ct_volume;    ///< empty: the phantom
      std::string                 label_volume; ///< empty: segment the CT
      std::string                 work_directory;
      bool                        reuse = true;
      std::string                 cut_held_by;
      std::string                 post_operative_skull;
      PhantomParameters           phantom;
      SegmentationParameters      segmentation;
      RegionOfInterest            roi;
      TetrahedralMeshParameters   mesh;
      OsteotomyParameters         osteotomy;
      RegistrationStageParameters registration;
      /// Subsection Preview: the point the preview's slices pass through.
      bool preview_point_given = false;
      Vec3 preview_point{{0., 0., 0.}};
    };

    /// What the stages made: the mesh file a Scene reads, and figures.
    struct PatientModel
    {
      std::string mesh_file;
      /// The boundary ids of each segment's join points on the mesh.
      std::vector<std::vector<unsigned int>> segment_boundary_ids;
      /// (stage, figure, value) for the report.
      std::vector<std::pair<std::string, std::string>> figures;
    };

    /**
     * Runs the patient stages, each writing files into the work directory
     * that the next reads, so that a user can enter at any stage with data
     * of their own: ct.nii.gz (the phantom; with its truth labels), then
     * labels.nii.gz with skin.ply/.vtp and skull.ply/.vtp, then
     * bone_parts.nii.gz and mesh.vtu/.msh. A stage whose inputs and
     * parameters are those of its last run (its .stamp file), made by the
     * same build of softface with the same ITK, VTK and CGAL (build_stamp()),
     * is skipped when reuse is on. Progress and figures go to @p log.
     */
    PatientModel
    build_patient_model(const PatientParameters        &parameters,
                        const std::vector<SegmentSeed> &segments,
                        std::ostream                   &log);

    /// The stages one at a time (the subcommands phantom, segment, mesh):
    /// each runs what it needs before it.
    enum class Stage
    {
      phantom,
      segmentation,
      mesh
    };
    PatientModel
    build_patient_model(const PatientParameters        &parameters,
                        const std::vector<SegmentSeed> &segments,
                        const Stage                     last_stage,
                        std::ostream                   &log);

    /**
     * 'softface register': the post-operative CT of subsection Registration
     * registered rigidly to the pre-operative CT (the file of 'CT volume',
     * or the phantom's, made or reused by the phantom stage) by mutual
     * information on the subvolume (register_rigid). Writes into
     * @p output_directory registration.csv (registration_table), the
     * post-operative CT resampled on the pre-operative grid
     * (postop_ct_registered.nii.gz) and each post-operative surface carried
     * into the pre-operative frame (<name>_registered.ply); the result and
     * the files go to @p out. A scene without a post-operative CT, a file
     * that cannot be read or a registration that fails is an Error.
     */
    void
    register_post_operative(const PatientParameters &parameters,
                            const std::string       &output_directory,
                            std::ostream            &out);
  } // namespace Patient
} // namespace softface

#endif

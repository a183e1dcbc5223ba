// What libsoftface_patient.so offers the core (backend.h), and the skull
// stages ('softface postop' and 'softface plan').

#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/patient/backend.h>
#include <softface/patient/image_io.h>
#include <softface/patient/planning_recovery.h>
#include <softface/patient/preview.h>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      int
      skull_stage(const PatientParameters           &patient,
                  const std::vector<SegmentSeed>    &seeds,
                  const std::vector<RigidTransform> &planned,
                  const std::string                 &stage,
                  std::ostream                      &out)
      {
        const auto parts =
          bone_part_surfaces(read_labels(patient.work_directory +
                                         "/bone_parts.nii.gz"),
                             seeds.size());

        if (stage == "postop")
          {
            write_surface(moved_skull(parts, planned),
                          patient.post_operative_skull);
            out << "Post-operative skull (each bone part moved by the "
                   "scene's Planning): "
                << patient.post_operative_skull << std::endl;
            return 0;
          }

        TriangleSurface post_operative;
        try
          {
            post_operative = read_surface(patient.post_operative_skull);
          }
        catch (const Error &e)
          {
            throw Error(std::string("Scene/Patient/Post-operative skull: ") +
                        e.what());
          }
        const auto motions =
          recover_motions(parts, post_operative, planned, IcpParameters());
        std::vector<std::string> names;
        for (const auto &seed : seeds)
          names.push_back(seed.name);
        const std::string section = planning_section(names, motions, parts);
        const std::string file    = patient.work_directory + "/planning.prm";
        open_output_file(file) << section;
        out << section << "Written to " << file
            << " (a scene takes it with 'include " << file << "')."
            << std::endl;
        return 0;
      }
    } // namespace
  }   // namespace Patient
} // namespace softface

extern "C" const softface::Patient::Backend *
softface_patient_backend()
{
  using namespace softface::Patient;
  static const Backend backend = [] {
    Backend b;
    b.build_patient_model =
      static_cast<PatientModel (*)(const PatientParameters &,
                                   const std::vector<SegmentSeed> &,
                                   Stage,
                                   std::ostream &)>(&build_patient_model);
    b.register_post_operative = &register_post_operative;
    b.skull_stage             = &skull_stage;
    b.preview                 = &preview;
    b.read_surface            = &read_surface;
    b.write_surface =
      static_cast<void (*)(const TriangleSurface &,
                           const std::string &,
                           const std::vector<PointField> &)>(&write_surface);
    return b;
  }();
  return &backend;
}

#ifndef softface_patient_backend_h
#define softface_patient_backend_h

#include <softface/patient/icp.h>
#include <softface/patient/pipeline.h>
#include <softface/patient/surface.h>

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// Raised when Backend or what it passes changes meaning.
    constexpr std::size_t backend_version = 2;

    /**
     * The patient pipeline's entry points that the core calls. They need
     * ITK, VTK and CGAL, whose 50-odd shared libraries took 0.1 s and 32 MB
     * of every softface process to load and relocate (`softface --help`,
     * median of 5: 0.52 s and 192 MB with them linked, 0.38 s and 160 MB
     * without; both with Open MPI's local transport, process.h), also for
     * scenes that never touch a patient. So the core does not
     * link libsoftface_patient.so: backend() loads it on first use. The
     * parameters of the patient subsections need none of those libraries
     * and live in the core (source/patient/front/).
     */
    struct Backend
    {
      /// What the core and the library were built with: a library from
      /// another build is refused instead of called with other layouts.
      std::size_t version            = backend_version;
      std::size_t size_of_backend    = sizeof(Backend);
      std::size_t size_of_parameters = sizeof(PatientParameters);

      /// build_patient_model() (pipeline.h).
      PatientModel (*build_patient_model)(const PatientParameters &,
                                          const std::vector<SegmentSeed> &,
                                          Stage,
                                          std::ostream &);
      /// register_post_operative() (pipeline.h).
      void (*register_post_operative)(const PatientParameters &,
                                      const std::string &,
                                      std::ostream &);
      /**
       * 'softface postop' (@p stage "postop": the pre-operative bone parts
       * moved by @p planned, written as the scene's post-operative skull)
       * and 'softface plan' ("plan": the planning recovered from the
       * post-operative skull by ICP from @p planned, written to
       * planning.prm in the work directory). Returns the exit code.
       */
      int (*skull_stage)(const PatientParameters &,
                         const std::vector<SegmentSeed> &,
                         const std::vector<RigidTransform> &planned,
                         const std::string                 &stage,
                         std::ostream &);
      /// preview() (preview.h).
      int (*preview)(const PatientParameters &,
                     const std::vector<SegmentSeed> &,
                     std::ostream &);
      /// read_surface() (surface.h).
      TriangleSurface (*read_surface)(const std::string &);
      /// write_surface() with fields (surface.h).
      void (*write_surface)(const TriangleSurface &,
                            const std::string &,
                            const std::vector<PointField> &);
    };

    /**
     * The pipeline, loaded on the first call: libsoftface_patient.so next to
     * the core library's file (a build's source/patient/ folder, or the same
     * folder in a copy or install), else by the dynamic linker's search
     * path. A library that cannot be loaded or comes from another build is
     * an Error naming it and the reason.
     */
    const Backend &
    backend();
  } // namespace Patient
} // namespace softface

/// What libsoftface_patient.so exports for Patient::backend().
extern "C" const softface::Patient::Backend *
softface_patient_backend();

#endif

#ifndef softface_patient_backend_h
#define softface_patient_backend_h

#include <softface/patient/icp.h>
#include <softface/patient/pipeline.h>
#include <softface/patient/surface.h>

#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * The patient pipeline's entry points that the core calls. They need
     * ITK, VTK and CGAL, whose 50-odd shared libraries took 0.1 s and 32 MB
     * of every softface process to load and relocate (`softface --help`:
     * 0.52 s and 192 MB against 0.38 s and 160 MB without them), also for
     * scenes that never touch a patient (issue 16). So the core does not
     * link libsoftface_patient.so: backend() loads it on first use. The
     * parameters of the patient subsections need none of those libraries
     * and live in the core (source/patient/front/).
     */
    struct Backend
    {
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
      /// read_surface() (surface.h).
      TriangleSurface (*read_surface)(const std::string &);
      /// write_surface() with fields (surface.h).
      void (*write_surface)(const TriangleSurface &,
                            const std::string &,
                            const std::vector<PointField> &);
    };

    /**
     * The pipeline, loaded on the first call (from the library next to
     * the core's, by the dynamic linker's search path, else from where the
     * build put it). A library that cannot be loaded is an Error naming it
     * and the loader's reason.
     */
    const Backend &
    backend();
  } // namespace Patient
} // namespace softface

/// What libsoftface_patient.so exports for Patient::backend().
extern "C" const softface::Patient::Backend *
softface_patient_backend();

#endif

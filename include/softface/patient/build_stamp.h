#ifndef softface_patient_build_stamp_h
#define softface_patient_build_stamp_h

#include <string>

namespace softface
{
  namespace Patient
  {
    /**
     * What a patient stage's result depends on besides its inputs and
     * parameters: the build of the patient library that makes it (GNU ld's
     * build ID, a hash of the linked library, or a hash of the library's
     * bytes where there is none) and the versions of ITK, VTK and CGAL. The
     * pipeline writes it into every stage's stamp, so that a stage made by
     * another build of the patient library is made again instead of reused;
     * a rebuild from the same code in the same build folder links the same
     * library and keeps the stages. Where no build can be told (no library
     * file found), the stamp never matches and no stage is reused.
     */
    std::string
    build_stamp();

    /// The build ID part alone (hexadecimal, or "fnv1a-" and a hash of the
    /// library file where it has none; empty where no library file is
    /// found), and the library it is of.
    std::string
    library_build_id(std::string *library_file = nullptr);
  } // namespace Patient
} // namespace softface

#endif

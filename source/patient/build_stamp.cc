// What a patient stage's result depends on besides its inputs (patient
// pipeline): this library's build and the versions of the libraries that
// shape a stage (ITK, VTK, CGAL). See include/softface/patient/build_stamp.h.

#include <softface/core/build_id.h>
#include <softface/patient/build_stamp.h>
#include <softface/patient/image_io.h>

#include <CGAL/version.h>

#include <unistd.h>
#include <vtkVersion.h>

#include <chrono>

namespace softface
{
  namespace Patient
  {
    std::string
    library_build_id(std::string *library_file)
    {
      return library_build_id_of(
        reinterpret_cast<const void *>(&library_build_id), library_file);
    }

    std::string
    build_stamp()
    {
      // No build to tell: a stamp no later run repeats, so nothing is reused.
      std::string id = library_build_id();
      if (id.empty())
        id = "unknown (process " + std::to_string(getpid()) + ", " +
             std::to_string(
               std::chrono::steady_clock::now().time_since_epoch().count()) +
             ")";
      return "softface patient library " + id + ", ITK " + itk_version() +
             ", VTK " + vtkVersion::GetVTKVersion() + ", CGAL " +
             CGAL_VERSION_STR + "\n";
    }
  } // namespace Patient
} // namespace softface

#ifndef softface_core_build_id_h
#define softface_core_build_id_h

#include <string>

namespace softface
{
  /**
   * The GNU build ID of the shared library (or executable) that holds
   * @p address, a function of it, as hexadecimal; where the linker wrote
   * none, "fnv1a-" and a hash of the library file; empty where no library
   * file is found. A rebuild from the same code in the same build folder
   * links the same library and keeps its ID; any change of the code
   * changes it. @p library_file, if given, receives the library's path.
   * What a stored result depends on beyond its inputs: the patient
   * pipeline's stages and the post-operative truths carry it.
   */
  std::string
  library_build_id_of(const void *address, std::string *library_file = nullptr);
} // namespace softface

#endif

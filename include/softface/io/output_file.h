#ifndef softface_io_output_file_h
#define softface_io_output_file_h

#include <fstream>
#include <string>

namespace softface
{
  /// A file opened for writing, or a clear error naming it.
  std::ofstream
  open_output_file(const std::string &filename);
} // namespace softface

#endif

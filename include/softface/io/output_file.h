#ifndef softface_io_output_file_h
#define softface_io_output_file_h

#include <fstream>
#include <string>

namespace softface
{
  /// A file opened for writing, or a clear error naming it.
  std::ofstream
  open_output_file(const std::string &filename);

  /**
   * Create @p directory (and its parents) for output, or throw one clear
   * error naming it and why (instead of std::filesystem's).
   */
  void
  create_output_directory(const std::string &directory);

  /// @p text as a CSV field: quoted if it holds a comma, quote or line
  /// break (a run's label "model, plan" does).
  std::string
  csv_field(const std::string &text);
} // namespace softface

#endif

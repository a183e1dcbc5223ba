// Opening output files (io): one message for a file that cannot be written.

#include <softface/core/error.h>
#include <softface/io/output_file.h>

namespace softface
{
  std::ofstream
  open_output_file(const std::string &filename)
  {
    std::ofstream out(filename);
    if (!out)
      throw Error("Cannot write '" + filename + "'.");
    return out;
  }
} // namespace softface

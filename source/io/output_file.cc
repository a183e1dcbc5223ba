// Opening output files (io): one message for a file that cannot be written.

#include <softface/core/error.h>
#include <softface/io/output_file.h>

#include <filesystem>
#include <system_error>

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

  void
  create_output_directory(const std::string &directory)
  {
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error || !std::filesystem::is_directory(directory))
      throw Error("Cannot create the output directory '" + directory + "' (" +
                  (error ? error.message() : std::string("not a directory")) +
                  ").");
  }

  std::string
  csv_field(const std::string &text)
  {
    if (text.find_first_of(",\"\n") == std::string::npos)
      return text;
    std::string quoted = "\"";
    for (const char c : text)
      quoted += (c == '"') ? std::string("\"\"") : std::string(1, c);
    return quoted + '"';
  }
} // namespace softface

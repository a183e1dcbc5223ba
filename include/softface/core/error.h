#ifndef softface_error_h
#define softface_error_h

#include <stdexcept>
#include <string>

namespace softface
{
  /**
   * An error in what the user gave softface (parameter file, mesh, planning).
   * The message is complete on its own: it names the file, line, cell or
   * parameter, and the executable prints it as the one line the user sees.
   */
  class Error : public std::runtime_error
  {
  public:
    explicit Error(const std::string &message)
        : std::runtime_error(message)
    {}
  };

  /// The message of any exception, without deal.II's stack-trace framing.
  std::string
  error_message(const std::exception &exception);
} // namespace softface

#endif

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

  /**
   * A number as a message writes it: six significant digits, exponent
   * where needed ("1e-300", "3000", "0.46"), never std::to_string's fixed
   * six decimals (0.000000 for 1e-7, 300 digits for 1e300).
   */
  std::string
  number_text(double value);

  /// The message of any exception, without deal.II's stack-trace framing.
  std::string
  error_message(const std::exception &exception);
} // namespace softface

#endif

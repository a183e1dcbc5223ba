// Errors in what the user gave softface (core): the one-line message of any
// exception, without deal.II's stack-trace framing.

#include <deal.II/base/exceptions.h>

#include <softface/core/error.h>

#include <sstream>

namespace softface
{
  std::string
  number_text(const double value)
  {
    std::ostringstream s;
    s << value;
    return s.str();
  }

  std::string
  error_message(const std::exception &exception)
  {
    std::string text;
    if (const auto *e = dynamic_cast<const dealii::ExceptionBase *>(&exception))
      {
        // print_info() holds deal.II's message without the file/line/stack
        // framing of what(), which points into deal.II, not the user's input.
        std::ostringstream s;
        e->print_info(s);
        text = s.str();
      }
    else
      text = exception.what();

    // One line: fold white space.
    std::string folded;
    for (const char c : text)
      {
        const bool space = (c == ' ' || c == '\n' || c == '\t' || c == '\r');
        if (space && (folded.empty() || folded.back() == ' '))
          continue;
        folded += space ? ' ' : c;
      }
    while (!folded.empty() && folded.back() == ' ')
      folded.pop_back();
    return folded;
  }
} // namespace softface

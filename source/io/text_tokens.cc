// Word-by-word reading of text mesh files (gmsh, legacy VTK) with line
// numbers, strict number parsing and counts bounded by the file's size;
// used by io/gmsh_reader.cc and io/vtk_reader.cc.

#include <softface/core/error.h>
#include <softface/core/mesh.h>
#include <softface/io/text_tokens.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace softface
{
  namespace Mesh
  {
    TextTokens::TextTokens(const std::string &filename)
        : filename(filename)
    {
      std::ifstream in(filename, std::ios::binary);
      if (!in)
        throw Error("Cannot open mesh file '" + filename + "'.");
      std::ostringstream all;
      all << in.rdbuf();
      text = all.str();
    }

    void
    TextTokens::skip_space()
    {
      while (position < text.size() &&
             std::isspace(static_cast<unsigned char>(text[position])))
        {
          if (text[position] == '\n')
            ++current_line;
          ++position;
        }
    }

    bool
    TextTokens::at_end()
    {
      skip_space();
      return position >= text.size();
    }

    std::string_view
    TextTokens::word(const std::string_view what)
    {
      skip_space();
      if (position >= text.size())
        {
          last_line = current_line;
          fail("the file ends where " + std::string(what) + " should be");
        }
      const std::size_t begin = position;
      while (position < text.size() &&
             !std::isspace(static_cast<unsigned char>(text[position])))
        ++position;
      last_line = current_line;
      return std::string_view(text).substr(begin, position - begin);
    }

    std::int64_t
    TextTokens::integer(const std::string_view what,
                        const std::int64_t     minimum,
                        const std::int64_t     maximum)
    {
      const std::string_view w     = word(what);
      std::int64_t           value = 0;
      const auto result = std::from_chars(w.data(), w.data() + w.size(), value);
      if (result.ec != std::errc() || result.ptr != w.data() + w.size())
        fail(std::string(what) + " '" + std::string(w) +
             "' is not a whole number");
      if (value < minimum || value > maximum)
        fail(std::string(what) + " " + std::string(w) + " is out of range (" +
             std::to_string(minimum) + " to " + std::to_string(maximum) + ")");
      return value;
    }

    double
    TextTokens::real(const std::string_view what)
    {
      const std::string_view w = word(what);
      // strtod needs a terminated string: a copy on the stack for the short
      // words numbers are (one per coordinate, on the reading's hot path).
      // (A longer word goes through a std::string.)
      char        buffer[64];
      std::string long_word;
      const char *text = buffer;
      if (w.size() < sizeof(buffer))
        {
          std::copy(w.begin(), w.end(), buffer);
          buffer[w.size()] = '\0';
        }
      else
        text = (long_word = std::string(w)).c_str();
      char        *end   = nullptr;
      const double value = std::strtod(text, &end);
      if (w.empty() || end != text + w.size())
        fail(std::string(what) + " '" + std::string(w) + "' is not a number");
      if (!std::isfinite(value))
        fail(std::string(what) + " is " + std::string(w) +
             ", not a finite number");
      return value;
    }

    double
    TextTokens::coordinate(const std::string_view what)
    {
      const double x = real(what);
      if (std::abs(x) > Mesh::largest_coordinate)
        fail(std::string(what) + " is " + Mesh::far_coordinate(x));
      return x;
    }

    void
    TextTokens::expect(const std::string &expected)
    {
      const std::string_view w = word("'" + expected + "'");
      if (w != expected)
        fail("expected '" + expected + "' but found '" +
             std::string(w.substr(0, 40)) + "'");
    }

    std::string
    TextTokens::rest_of_line()
    {
      const std::size_t begin = position;
      while (position < text.size() && text[position] != '\n')
        ++position;
      std::string rest  = text.substr(begin, position - begin);
      const auto  first = rest.find_first_not_of(" \t\r");
      const auto  last  = rest.find_last_not_of(" \t\r");
      return first == std::string::npos ? "" :
                                          rest.substr(first, last - first + 1);
    }

    std::string
    TextTokens::line_text(const std::string_view what)
    {
      // Move to the start of the next line unless at the file's start.
      if (position > 0)
        {
          while (position < text.size() && text[position] != '\n')
            ++position;
          if (position < text.size())
            {
              ++position;
              ++current_line;
            }
        }
      if (position >= text.size())
        {
          last_line = current_line;
          fail("the file ends where " + std::string(what) + " should be");
        }
      last_line = current_line;
      return rest_of_line();
    }

    std::uint64_t
    TextTokens::count(const std::string_view what, const std::uint64_t words)
    {
      const std::int64_t n = integer(what, 0);
      // Each word takes at least one character and one separator.
      const std::uint64_t left = text.size() - position;
      if (static_cast<std::uint64_t>(n) > left / (2 * words))
        fail(std::string(what) + " is " + std::to_string(n) +
             ", more than the rest of the file (" + std::to_string(left) +
             " bytes) can hold");
      return n;
    }

    bool
    TextTokens::next_is(const std::string &expected)
    {
      skip_space();
      return text.compare(position, expected.size(), expected) == 0 &&
             (position + expected.size() == text.size() ||
              std::isspace(
                static_cast<unsigned char>(text[position + expected.size()])));
    }

    void
    TextTokens::skip_to_empty_line()
    {
      // Past the current line, then to the end of the first blank one.
      while (position < text.size())
        {
          while (position < text.size() && text[position] != '\n')
            ++position;
          if (position >= text.size())
            break;
          ++position;
          ++current_line;
          std::size_t end = position;
          while (end < text.size() && text[end] != '\n' &&
                 std::isspace(static_cast<unsigned char>(text[end])))
            ++end;
          if (end >= text.size() || text[end] == '\n')
            {
              position = end;
              return;
            }
        }
    }

    void
    TextTokens::skip_to(const std::string &end_marker)
    {
      while (word("'" + end_marker + "'") != end_marker)
        ;
    }

    std::string
    TextTokens::where() const
    {
      return filename + ":" + std::to_string(last_line) + ": ";
    }

    void
    TextTokens::fail(const std::string &message) const
    {
      throw Error("Cannot read mesh file '" + filename + "', line " +
                  std::to_string(last_line) + ": " + message + ".");
    }
  } // namespace Mesh
} // namespace softface

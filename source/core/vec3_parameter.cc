// Points and directions given as parameters ('x, y, z'), read one way with
// one message for everything that is not three numbers.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/vec3_parameter.h>

#include <cmath>

namespace softface
{
  std::array<double, 3>
  parse_vec3(const std::string &text, const std::string &where)
  {
    const auto            items = dealii::Utilities::split_string_list(text);
    std::array<double, 3> v;
    bool                  ok = items.size() == 3;
    for (unsigned int d = 0; ok && d < 3; ++d)
      try
        {
          v[d] = dealii::Utilities::string_to_double(items[d]);
          ok   = std::isfinite(v[d]);
        }
      catch (...)
        {
          ok = false;
        }
    if (!ok)
      throw Error(where + ": expected three numbers 'x, y, z' (got '" + text +
                  "').");
    return v;
  }
} // namespace softface

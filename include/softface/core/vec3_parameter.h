#ifndef softface_core_vec3_parameter_h
#define softface_core_vec3_parameter_h

#include <array>
#include <string>

namespace softface
{
  /**
   * A parameter's 'x, y, z' (a point or a direction); anything else is an
   * Error naming @p where, the parameter's path.
   */
  std::array<double, 3>
  parse_vec3(const std::string &text, const std::string &where);
} // namespace softface

#endif

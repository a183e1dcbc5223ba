// The registry of the scene file's sections that code above the simulator
// reads.

#include <softface/core/error.h>
#include <softface/core/parameter_sections.h>

#include <map>

namespace softface
{
  namespace
  {
    // A function-local static: registrations run from other translation
    // units' static initialisers, in an order no one controls.
    std::map<std::string, std::function<void(ParameterHandler &)>> &
    sections()
    {
      static std::map<std::string, std::function<void(ParameterHandler &)>>
        registered;
      return registered;
    }
  } // namespace

  bool
  register_parameter_section(
    const std::string                             &name,
    const std::function<void(ParameterHandler &)> &declare_parameters)
  {
    if (!sections().emplace(name, declare_parameters).second)
      throw Error("Parameter section '" + name + "' is registered twice.");
    return true;
  }

  void
  declare_registered_parameter_sections(ParameterHandler &prm)
  {
    for (const auto &[name, declare] : sections())
      declare(prm);
  }
} // namespace softface

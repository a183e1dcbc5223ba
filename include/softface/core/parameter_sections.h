#ifndef softface_core_parameter_sections_h
#define softface_core_parameter_sections_h

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <string>

namespace softface
{
  using namespace dealii;

  /**
   * Sections of a scene file that belong to code above the simulator (the
   * Serve section of softface serve): each registers the declaration of its
   * section from a static initialiser, and the simulator declares every
   * registered section, so that a scene file may hold them and
   * --print-parameters lists them, without the simulator knowing who reads
   * them.
   */
  bool
  register_parameter_section(
    const std::string                             &name,
    const std::function<void(ParameterHandler &)> &declare_parameters);

  /// Declares every registered section in @p prm.
  void
  declare_registered_parameter_sections(ParameterHandler &prm);
} // namespace softface

#endif

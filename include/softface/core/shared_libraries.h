#ifndef softface_core_shared_libraries_h
#define softface_core_shared_libraries_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace softface
{
  using namespace dealii;

  /**
   * Plugins from outside softface's tree, as ASPECT's 'Additional shared
   * libraries': a scene names shared libraries (models, effects, mesh
   * sources or outputs built against an installed softface, see
   * doc/extending.md), which are loaded before its parameters are declared,
   * so that their one-line registrations add them to the plugin families.
   */
  namespace SharedLibraries
  {
    /// The top-level entry 'Additional shared libraries'.
    void
    declare_parameters(ParameterHandler &prm);

    /**
     * Load the libraries that the entry of @p prm lists (relative paths
     * are taken from @p input_directory; a library loaded already is not
     * loaded again). A library that cannot be loaded is an Error naming
     * the entry, the file and the loader's reason.
     */
    void
    load(ParameterHandler &prm, const std::string &input_directory);
  } // namespace SharedLibraries
} // namespace softface

#endif

// Plugins from outside the tree (core): the libraries a scene names in
// 'Additional shared libraries', loaded with dlopen before its parameters
// are declared.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/shared_libraries.h>

#include <dlfcn.h>

#include <filesystem>

namespace softface
{
  namespace SharedLibraries
  {
    void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry(
        "Additional shared libraries",
        "",
        Patterns::List(Patterns::FileName()),
        "Shared libraries to load before the scene is read, each holding "
        "plugins (models, effects, mesh sources, outputs) built against an "
        "installed softface (doc/extending.md). Relative paths are taken "
        "from the parameter file's folder.");
    }

    void
    load(ParameterHandler &prm, const std::string &input_directory)
    {
      for (const std::string &name :
           Utilities::split_string_list(prm.get("Additional shared libraries")))
        {
          std::filesystem::path file(name);
          // "./" keeps dlopen from searching the library path instead.
          if (file.is_relative())
            file = std::filesystem::path(
                     input_directory.empty() ? "." : input_directory) /
                   file;
          if (!std::filesystem::is_regular_file(file))
            throw Error("Additional shared libraries: '" + file.string() +
                        "' is not a file.");
          // RTLD_GLOBAL: a library's plugins may use another's symbols.
          // Never closed: its registrations live as long as the process.
          if (dlopen(file.c_str(), RTLD_NOW | RTLD_GLOBAL) == nullptr)
            throw Error("Additional shared libraries: cannot load '" +
                        file.string() + "': " + dlerror());
        }
    }
  } // namespace SharedLibraries
} // namespace softface

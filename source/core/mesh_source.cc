// The mesh source plugin family (core): the registry that the one-line
// SOFTFACE_REGISTER_MESH_SOURCE fills and the 'Scene/Mesh source' entry that
// chooses one.

#include <softface/core/error.h>
#include <softface/core/mesh_source.h>

#include <map>

namespace softface
{
  namespace MeshSources
  {
    namespace
    {
      // Function-local so that registrations from static initialisers in
      // any translation unit find it constructed.
      std::map<std::string, Registration> &
      registry()
      {
        static std::map<std::string, Registration> sources;
        return sources;
      }
    } // namespace

    void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &first_pass_names)
    {
      std::string names, description;
      for (const auto &[name, registration] : registry())
        {
          names += (names.empty() ? "" : "|") + name;
          description += (description.empty() ? "" : ", ") + ("'" + name) +
                         "' " + registration.description;
        }
      prm.declare_entry("Mesh source",
                        "cube",
                        Patterns::Selection(names),
                        "Where the tetrahedral mesh comes from: " +
                          description + ".");
      for (const auto &[name, registration] : registry())
        registration.declare_parameters(prm, first_pass_names);
    }

    std::vector<std::string>
    names_from_first_pass(ParameterHandler &prm)
    {
      std::vector<std::string> names;
      for (const auto &[name, registration] : registry())
        if (registration.names_from_first_pass)
          for (const auto &n : registration.names_from_first_pass(prm))
            names.push_back(n);
      return names;
    }

    std::unique_ptr<Interface>
    create(ParameterHandler &prm)
    {
      const std::string name   = prm.get("Mesh source");
      const auto        source = registry().find(name);
      // The entry's pattern lists the registered sources only.
      AssertThrow(source != registry().end(),
                  ExcMessage("Unknown mesh source '" + name + "'."));
      return source->second.factory();
    }

    std::string
    describe_registered()
    {
      std::string text;
      for (const auto &[name, registration] : registry())
        text += "  " + name + ": " + registration.description + "\n";
      return text;
    }

    namespace internal
    {
      bool
      register_mesh_source(const std::string &name, Registration registration)
      {
        if (!registry().emplace(name, std::move(registration)).second)
          throw Error("Mesh source '" + name + "' is registered twice.");
        return true;
      }
    } // namespace internal
  }   // namespace MeshSources
} // namespace softface

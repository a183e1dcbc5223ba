// The mesh source plugin family (core): the registry that the one-line
// SOFTFACE_REGISTER_MESH_SOURCE fills and the 'Scene/Mesh source' entry that
// chooses one.

#include <softface/core/mesh_source.h>
#include <softface/core/plugin_registry.h>

namespace softface
{
  namespace MeshSources
  {
    namespace
    {
      // Function-local so that registrations from static initialisers in
      // any translation unit find it constructed.
      NamedRegistry<Registration> &
      registry()
      {
        static NamedRegistry<Registration> sources("mesh source");
        return sources;
      }
    } // namespace

    void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &first_pass_names)
    {
      std::string description;
      for (const auto &[name, registration] : registry())
        description += (description.empty() ? "" : ", ") + ("'" + name) + "' " +
                       registration.description;
      prm.declare_entry("Mesh source",
                        "cube",
                        Patterns::Selection(registry().joined_names("|")),
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
      const std::string   name   = prm.get("Mesh source");
      const Registration *source = registry().find(name);
      // The entry's pattern lists the registered sources only.
      AssertThrow(source != nullptr,
                  ExcMessage("Unknown mesh source '" + name + "'."));
      return source->factory();
    }

    std::string
    describe_registered()
    {
      return registry().describe();
    }

    namespace internal
    {
      bool
      register_mesh_source(const std::string &name, Registration registration)
      {
        return registry().add(name, std::move(registration));
      }
    } // namespace internal
  }   // namespace MeshSources
} // namespace softface

// The effect plugin layer (effects): the registry that the one-line
// SOFTFACE_REGISTER_EFFECT fills, the Effects section of a parameter file,
// and the check that every selected model honours every selected effect.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/effects/interface.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

namespace softface
{
  namespace Effects
  {
    namespace
    {
      // Function-local so that registrations from static initialisers in
      // any translation unit find it constructed.
      PluginRegistry<Interface> &
      registry()
      {
        static PluginRegistry<Interface> effects("effect", "an", "Effects");
        return effects;
      }

      std::string
      contribution_names(const unsigned int flags)
      {
        std::string names;
        const auto  add = [&](const std::string &name) {
          names += (names.empty() ? "" : " and ") + name;
        };
        if (flags & SceneEffects::cell_materials)
          add("tissues per cell");
        if (flags & SceneEffects::body_forces)
          add("body forces");
        if (flags & SceneEffects::free_vertex_constraints)
          add("constraints on free vertices");
        return names;
      }
    } // namespace

    void
    Interface::parse_parameters(ParameterHandler &)
    {}

    Region
    parse_region(const std::string &entry, const std::string &text)
    {
      Region region;
      if (Utilities::trim(text).empty())
        return region;
      const auto          parts = Utilities::split_string_list(text);
      std::vector<double> values;
      for (const std::string &part : parts)
        {
          char        *end   = nullptr;
          const double value = std::strtod(part.c_str(), &end);
          if (part.empty() || *end != '\0' || !std::isfinite(value))
            {
              values.clear();
              break;
            }
          values.push_back(value);
        }
      if (values.size() != 6 || values[0] > values[1] ||
          values[2] > values[3] || values[4] > values[5])
        throw Error(entry + ": '" + text +
                    "' is not a box 'x0, x1, y0, y1, z0, z1' with x0 <= x1, "
                    "y0 <= y1, z0 <= z1 (mm).");
      region.everywhere = false;
      for (unsigned int d = 0; d < 3; ++d)
        {
          region.lower[d] = values[2 * d];
          region.upper[d] = values[2 * d + 1];
        }
      return region;
    }

    void
    declare_active_set_iterations(ParameterHandler &prm)
    {
      prm.declare_entry("Maximum active-set iterations",
                        "50",
                        Patterns::Integer(1),
                        "A FEM solve whose set of vertices in contact still "
                        "changes after this many solves stops with an error.");
    }

    std::string
    Interface::prepare_mesh(Scene &) const
    {
      return {};
    }

    void
    Interface::declare_rules(Scene &) const
    {}

    std::string
    Interface::apply(Scene &scene) const
    {
      declare_rules(scene);
      const std::string line = check_and_add(scene);
      scene.apply_rules();
      return line;
    }

    bool
    internal::register_effect(const std::string &name,
                              Registration       registration)
    {
      return registry().add(name, std::move(registration));
    }

    std::vector<std::string>
    registered_names()
    {
      return registry().names();
    }

    void
    declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Effects");
      prm.declare_entry("Effects",
                        "",
                        Patterns::List(Patterns::Anything(), 0),
                        "The effects the scene calls for beyond homogeneous "
                        "tissue moved by its bones; none by default, and a "
                        "scene pays only for those it names. Available: " +
                          registry().joined_names() + ".");
      registry().declare_subsections(prm);
      prm.leave_subsection();
    }

    std::vector<std::string>
    selected_names(ParameterHandler &prm)
    {
      return registry().selected(prm);
    }

    std::unique_ptr<Interface>
    create(const std::string &name, ParameterHandler &prm)
    {
      try
        {
          return registry().create(name, prm);
        }
      catch (const Error &e)
        {
          throw Error("Effects/" + name + "/" + e.what());
        }
    }

    void
    check_supported(const std::string &model,
                    const unsigned int honoured,
                    const std::string &effect_name,
                    const Interface   &effect)
    {
      const unsigned int missing = effect.contributions() & ~honoured;
      if (missing != 0)
        throw Error("Model '" + model + "' cannot simulate the effect '" +
                    effect_name + "': it does not honour " +
                    contribution_names(missing) +
                    ". Remove the effect from Effects/Effects or the model "
                    "from Models/Models.");
    }

    std::map<types::material_id, double>
    parse_material_values(const std::string &entry, const std::string &text)
    {
      std::map<types::material_id, double> values;
      for (const std::string &pair : Utilities::split_string_list(text))
        {
          const auto parts = Utilities::split_string_list(pair, ':');
          // Strict: the whole text of each part must be the number.
          long   id    = -1;
          double value = std::nan("");
          if (parts.size() == 2 && !parts[0].empty() && !parts[1].empty())
            {
              char *end = nullptr;
              id        = std::strtol(parts[0].c_str(), &end, 10);
              if (*end != '\0')
                id = -1;
              value = std::strtod(parts[1].c_str(), &end);
              if (*end != '\0')
                value = std::nan("");
            }
          if (parts.size() != 2 || id < 0 || id > 255 || !std::isfinite(value))
            throw Error(entry + ": '" + pair +
                        "' is not 'material id: value' (ids 0 to 255, "
                        "finite values).");
          if (values.count(id) != 0)
            throw Error(entry + ": material id " + std::to_string(id) +
                        " is listed twice.");
          values[id] = value;
        }
      return values;
    }

    std::string
    describe_registered()
    {
      return registry().describe();
    }
  } // namespace Effects
} // namespace softface

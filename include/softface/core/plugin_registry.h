#ifndef softface_core_plugin_registry_h
#define softface_core_plugin_registry_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <softface/core/error.h>

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Plugins of one kind by name, each with its @p Registration (which has a
   * 'description'), filled from static initialisers: what every plugin
   * family shares (models, effects, outputs, mesh sources).
   */
  template <typename Registration>
  class NamedRegistry
  {
  public:
    /// @p kind names a plugin in messages ("mesh source").
    explicit NamedRegistry(const std::string &kind)
        : kind(kind)
    {}

    /// A second registration under a name would silently replace the
    /// first: a programming error, reported in every build.
    bool
    add(const std::string &name, Registration registration)
    {
      if (!plugins.emplace(name, std::move(registration)).second)
        throw Error(capitalised(kind) + " '" + name + "' is registered twice.");
      return true;
    }

    /// The registration of @p name, or nullptr.
    const Registration *
    find(const std::string &name) const
    {
      const auto entry = plugins.find(name);
      return entry == plugins.end() ? nullptr : &entry->second;
    }

    /// In alphabetical order.
    std::vector<std::string>
    names() const
    {
      std::vector<std::string> list;
      for (const auto &entry : plugins)
        list.push_back(entry.first);
      return list;
    }

    /// The names joined by @p separator (", " for a documentation, "|" for
    /// a Patterns::Selection).
    std::string
    joined_names(const std::string &separator = ", ") const
    {
      std::string text;
      for (const auto &entry : plugins)
        text += (text.empty() ? "" : separator) + entry.first;
      return text;
    }

    /// One line per plugin: "  name: description" (for --help).
    std::string
    describe() const
    {
      std::string text;
      for (const auto &[name, registration] : plugins)
        text += "  " + name + ": " + registration.description + "\n";
      return text;
    }

    /// (name, registration) pairs in alphabetical order.
    auto
    begin() const
    {
      return plugins.begin();
    }
    auto
    end() const
    {
      return plugins.end();
    }

  private:
    static std::string
    capitalised(std::string word)
    {
      if (!word.empty())
        word[0] = std::toupper(static_cast<unsigned char>(word[0]));
      return word;
    }

    const std::string                   kind;
    std::map<std::string, Registration> plugins;
  };

  /**
   * The plugins of one kind (models, effects). Each registers itself, from a
   * static initialiser, under the name a parameter file uses, with a
   * description, the declaration of its own subsection and a factory. A
   * parameter file selects some of them in the list entry of the kind's
   * section ("Models/Models", "Effects/Effects"); each plugin has a
   * subsection of that section.
   */
  template <typename Plugin>
  class PluginRegistry
  {
  public:
    struct Registration
    {
      std::string                              description;
      std::function<void(ParameterHandler &)>  declare_parameters;
      std::function<std::unique_ptr<Plugin>()> factory;
    };

    /**
     * @p kind names a plugin in messages ("model"), @p article goes with it
     * ("a"), @p section is the parameter section and its list entry
     * ("Models").
     */
    PluginRegistry(const std::string &kind,
                   const std::string &article,
                   const std::string &section)
        : kind(kind)
        , article(article)
        , section(section)
        , plugins(kind)
    {}

    /// Throws on a second registration under @p name.
    bool
    add(const std::string &name, Registration registration)
    {
      return plugins.add(name, std::move(registration));
    }

    /// In alphabetical order.
    std::vector<std::string>
    names() const
    {
      return plugins.names();
    }

    /// "a, b, c", for an entry's documentation.
    std::string
    joined_names() const
    {
      return plugins.joined_names();
    }

    /// Every plugin's subsection (the handler is inside the section).
    void
    declare_subsections(ParameterHandler &prm) const
    {
      for (const auto &[name, registration] : plugins)
        {
          prm.enter_subsection(name);
          registration.declare_parameters(prm);
          prm.leave_subsection();
        }
    }

    /// The names in the section's list entry; an unknown or repeated one is
    /// a clear error (whose message does not list every plugin: softface
    /// --help does).
    std::vector<std::string>
    selected(ParameterHandler &prm) const
    {
      prm.enter_subsection(section);
      const auto list = Utilities::split_string_list(prm.get(section));
      prm.leave_subsection();
      const std::string entry = section + "/" + section + ": '";
      for (unsigned int i = 0; i < list.size(); ++i)
        {
          if (plugins.find(list[i]) == nullptr)
            throw Error(entry + list[i] + "' is not " + article + " " + kind +
                        " ('softface --help' lists them).");
          if (std::find(list.begin(), list.begin() + i, list[i]) !=
              list.begin() + i)
            throw Error(entry + list[i] + "' is listed twice.");
        }
      return list;
    }

    /// Create the plugin @p name and let it parse its subsection.
    std::unique_ptr<Plugin>
    create(const std::string &name, ParameterHandler &prm) const
    {
      const Registration *registration = plugins.find(name);
      if (registration == nullptr)
        throw Error("Unknown " + kind + " '" + name + "'.");
      auto plugin = registration->factory();
      prm.enter_subsection(section);
      prm.enter_subsection(name);
      try
        {
          plugin->parse_parameters(prm);
        }
      catch (...)
        {
          prm.leave_subsection();
          prm.leave_subsection();
          throw;
        }
      prm.leave_subsection();
      prm.leave_subsection();
      return plugin;
    }

    /// One line per plugin: "  name: description" (for --help).
    std::string
    describe() const
    {
      return plugins.describe();
    }

  private:
    const std::string           kind;
    const std::string           article;
    const std::string           section;
    NamedRegistry<Registration> plugins;
  };
} // namespace softface

#endif

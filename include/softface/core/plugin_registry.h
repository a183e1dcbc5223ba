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
    {}

    /// A second registration under a name would silently replace the
    /// first: a programming error, reported in every build.
    bool
    add(const std::string &name, Registration registration)
    {
      if (plugins.count(name) != 0)
        throw Error(capitalised(kind) + " '" + name + "' is registered twice.");
      plugins[name] = std::move(registration);
      return true;
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

    /// "a, b, c", for an entry's documentation.
    std::string
    joined_names() const
    {
      std::string text;
      for (const auto &entry : plugins)
        text += (text.empty() ? "" : ", ") + entry.first;
      return text;
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
          if (plugins.count(list[i]) == 0)
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
      const auto entry = plugins.find(name);
      if (entry == plugins.end())
        throw Error("Unknown " + kind + " '" + name + "'.");
      auto plugin = entry->second.factory();
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
      std::string text;
      for (const auto &[name, registration] : plugins)
        text += "  " + name + ": " + registration.description + "\n";
      return text;
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
    const std::string                   article;
    const std::string                   section;
    std::map<std::string, Registration> plugins;
  };
} // namespace softface

#endif

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/models/interface.h>

#include <map>

namespace softface
{
  namespace Models
  {
    namespace
    {
      // Function-local so that registrations from static initialisers in
      // any translation unit find it constructed.
      std::map<std::string, internal::Registration> &
      registry()
      {
        static std::map<std::string, internal::Registration> models;
        return models;
      }
    } // namespace

    bool
    internal::register_model(const std::string &name, Registration registration)
    {
      Assert(registry().count(name) == 0,
             ExcMessage("Model '" + name + "' is registered twice."));
      registry()[name] = std::move(registration);
      return true;
    }

    void
    Interface::parse_parameters(ParameterHandler &)
    {}

    std::pair<const DoFHandler<3> *, const Vector<double> *>
    Interface::displacement_field() const
    {
      return {nullptr, nullptr};
    }

    const Statistics &
    Interface::statistics() const
    {
      return stats;
    }

    void
    Interface::set_progress_stream(std::ostream *stream)
    {
      progress = stream;
    }

    std::vector<std::string>
    registered_names()
    {
      std::vector<std::string> names;
      for (const auto &entry : registry())
        names.push_back(entry.first);
      return names;
    }

    void
    declare_parameters(ParameterHandler &prm)
    {
      std::string selection;
      for (const std::string &name : registered_names())
        selection += (selection.empty() ? "" : "|") + name;

      prm.enter_subsection("Models");
      prm.declare_entry("Models",
                        "linear fem",
                        Patterns::MultipleSelection(selection),
                        "The soft-tissue models to run on the scene, side by "
                        "side on the same mesh and join points. Available: " +
                          selection + ".");
      for (const auto &[name, registration] : registry())
        {
          prm.enter_subsection(name);
          registration.declare_parameters(prm);
          prm.leave_subsection();
        }
      prm.leave_subsection();
    }

    std::vector<std::string>
    selected_names(ParameterHandler &prm)
    {
      prm.enter_subsection("Models");
      const auto names = Utilities::split_string_list(prm.get("Models"));
      prm.leave_subsection();
      return names;
    }

    std::unique_ptr<Interface>
    create(const std::string &name, ParameterHandler &prm)
    {
      const auto entry = registry().find(name);
      if (entry == registry().end())
        throw Error("Unknown model '" + name + "'.");
      auto model = entry->second.factory();
      prm.enter_subsection("Models");
      prm.enter_subsection(name);
      model->parse_parameters(prm);
      prm.leave_subsection();
      prm.leave_subsection();
      return model;
    }

    std::string
    describe_registered()
    {
      std::string text;
      for (const auto &[name, registration] : registry())
        text += "  " + name + ": " + registration.description + "\n";
      return text;
    }
  } // namespace Models
} // namespace softface

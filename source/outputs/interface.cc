// The output plugin family (outputs): the registry that the one-line
// SOFTFACE_REGISTER_OUTPUT fills, and what every output shares.

#include <softface/core/plugin_registry.h>
#include <softface/outputs/interface.h>

#include <cctype>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      // Function-local so that registrations from static initialisers in
      // any translation unit find it constructed.
      NamedRegistry<Registration> &
      registry()
      {
        static NamedRegistry<Registration> outputs("output");
        return outputs;
      }
    } // namespace

    std::string
    file_name_of(const std::string &model)
    {
      // Letters, digits, '.', '-' and '+' stay; any run of other characters
      // (spaces, the comma before a plan's name) becomes one '_'.
      std::string name;
      for (const char c : model)
        if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' ||
            c == '-' || c == '+')
          name += c;
        else if (name.empty() || name.back() != '_')
          name += '_';
      return name;
    }

    void
    Interface::prepare(const Run &, std::ostream &)
    {}

    void
    Interface::add_answer(const Run &,
                          const Report::ModelRun &,
                          Models::Interface &,
                          const bool)
    {}

    void
    declare_parameters(ParameterHandler &prm)
    {
      for (const auto &[name, registration] : registry())
        registration.declare_parameters(prm);
    }

    std::vector<std::unique_ptr<Interface>>
    create_all(ParameterHandler &prm, const std::string &input_directory)
    {
      std::vector<std::unique_ptr<Interface>> outputs;
      for (const auto &[name, registration] : registry())
        {
          outputs.push_back(registration.factory());
          outputs.back()->parse_parameters(prm, input_directory);
        }
      return outputs;
    }

    std::vector<std::string>
    registered_names()
    {
      return registry().names();
    }

    std::string
    describe_registered()
    {
      return registry().describe();
    }

    namespace internal
    {
      bool
      register_output(const std::string &name, Registration registration)
      {
        return registry().add(name, std::move(registration));
      }
    } // namespace internal
  }   // namespace Outputs
} // namespace softface

// The Serve section (serve): where `softface serve` listens, which models it
// offers and how far the page's sliders may move a bone.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/parameter_sections.h>
#include <softface/serve/parameters.h>

namespace softface
{
  namespace Serve
  {
    namespace
    {
      [[maybe_unused]] const bool registered_section =
        register_parameter_section("Serve", &Parameters::declare_parameters);
    } // namespace

    void
    Parameters::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Serve");
      prm.declare_entry("Address",
                        "127.0.0.1",
                        Patterns::Anything(),
                        "The address 'softface serve' listens on: the local "
                        "machine only by default; 0.0.0.0 serves every "
                        "network the machine is on (no access control).");
      prm.declare_entry("Port",
                        "8080",
                        Patterns::Integer(0, 65535),
                        "The port; 0: any free port (printed).");
      prm.declare_entry("Models",
                        "linear fem, mass tensor",
                        Patterns::List(Patterns::Anything()),
                        "The models the page offers, each re-planning from "
                        "its response basis: models whose answer is linear "
                        "in the motion (linear fem, mass tensor). Their "
                        "parameters are those of the Models section.");
      prm.declare_entry("Translation limit",
                        "20",
                        Patterns::Double(0.),
                        "Largest translation (mm, per axis) the page may ask "
                        "for; a request past it is refused.");
      prm.declare_entry("Rotation limit",
                        "30",
                        Patterns::Double(0., 90.),
                        "Largest rotation (degrees, per axis) the page may "
                        "ask for; a request past it is refused.");
      prm.declare_entry("Web directory",
                        "",
                        Patterns::Anything(),
                        "The page's files (index.html, app.js and "
                        "node_modules/three, installed by ./run.sh). Empty: "
                        "the web/ folder of the source tree softface was "
                        "built from.");
      prm.leave_subsection();
    }

    void
    Parameters::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Serve");
      address           = prm.get("Address");
      port              = prm.get_integer("Port");
      models            = Utilities::split_string_list(prm.get("Models"));
      translation_limit = prm.get_double("Translation limit");
      rotation_limit    = prm.get_double("Rotation limit");
      web_directory     = prm.get("Web directory");
      prm.leave_subsection();
      if (models.empty())
        throw Error("Serve/Models: name at least one model.");
    }
  } // namespace Serve
} // namespace softface

// The parameters of a scene file (simulator): every section declared (the
// Output section here, the others by their owners), read in two passes (the
// first finds the names that declare subsections: segments, moved segments,
// cuts, plannings), with the 'include' lines checked first.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/parameter_sections.h>
#include <softface/core/planning.h>
#include <softface/core/planning_list.h>
#include <softface/core/scene.h>
#include <softface/core/shared_libraries.h>
#include <softface/effects/interface.h>
#include <softface/models/interface.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/skin_output.h>
#include <softface/simulator/parameters.h>
#include <softface/simulator/simulator.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace softface
{
  namespace
  {
    // The names a file lists in a given entry, read tolerantly (pass one).
    void
    parse_tolerantly(const std::string &filename, ParameterHandler &prm)
    {
      prm.parse_input(filename, "", /*skip_undefined=*/true);
    }

    /**
     * Follow the 'include' lines of a parameter file before deal.II does:
     * it would recurse without end on a file that includes itself. Paths
     * are read as deal.II reads them (relative to the working directory).
     */
    void
    check_includes(const std::string &filename, std::vector<std::string> chain)
    {
      constexpr unsigned int max_depth = 10;
      chain.push_back(filename);
      std::ifstream in(filename);
      std::string   line;
      for (unsigned int number = 1; std::getline(in, line); ++number)
        {
          const auto hash = line.find('#');
          if (hash != std::string::npos)
            line.erase(hash);
          line = Utilities::trim(line);
          if (line.rfind("include", 0) != 0 ||
              (line.size() > 7 && !std::isspace(line[7])))
            continue;
          const std::string included = Utilities::trim(line.substr(7));
          const std::string where =
            filename + ":" + std::to_string(number) + ": ";
          if (std::find(chain.begin(), chain.end(), included) != chain.end())
            throw Error(where + "'include " + included +
                        "' includes a file that is already being read.");
          if (chain.size() >= max_depth)
            throw Error(where + "'include' nested deeper than " +
                        std::to_string(max_depth) + " files.");
          if (!std::filesystem::is_regular_file(included) ||
              !std::ifstream(included))
            throw Error(where + "cannot open included file '" + included +
                        "'.");
          check_includes(included, chain);
        }
    }
  } // namespace

  void
  OutputParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    prm.declare_entry("Output directory",
                      "output",
                      Patterns::Anything(),
                      "Folder for summary.csv, solution.vtu, the input and "
                      "the expanded parameter file (relative to the "
                      "working directory; created if missing).");
    prm.declare_entry("Reference model",
                      "linear fem",
                      Patterns::Anything(),
                      "The model every other model's displacement is "
                      "compared to in the table and summary.csv (largest "
                      "and mean difference over the free vertices). No "
                      "comparison when it is not among Models/Models or "
                      "fails.");
    Outputs::declare_parameters(prm);
    prm.leave_subsection();
  }

  void
  OutputParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    directory       = prm.get("Output directory");
    reference_model = prm.get("Reference model");
    prm.leave_subsection();
  }

  void
  Simulator::declare_parameters(ParameterHandler               &prm,
                                const std::vector<std::string> &segment_names,
                                const std::vector<std::string> &moved_segments,
                                const std::vector<std::string> &cut_names,
                                const std::vector<std::string> &plan_names)
  {
    SharedLibraries::declare_parameters(prm);
    Scene::declare_parameters(prm, segment_names, cut_names);
    PlanningList::declare_parameters(prm, moved_segments, plan_names);
    Models::declare_parameters(prm);
    Effects::declare_parameters(prm);
    SkinParameters::declare_parameters(prm);
    OutputParameters::declare_parameters(prm);
    declare_registered_parameter_sections(prm);
  }

  void
  Simulator::read_parameters(const std::string &filename, ParameterHandler &prm)
  {
    // A directory opens as a stream on Linux (and reads as empty).
    if (!std::filesystem::is_regular_file(filename) || !std::ifstream(filename))
      throw Error("Cannot open parameter file '" + filename +
                  "' (not a readable file).");
    check_includes(filename, {});

    // Plugins from outside the tree register themselves when loaded, before
    // anything is declared.
    {
      ParameterHandler libraries;
      SharedLibraries::declare_parameters(libraries);
      parse_tolerantly(filename, libraries);
      try
        {
          SharedLibraries::load(
            libraries, std::filesystem::path(filename).parent_path().string());
        }
      catch (const Error &e)
        {
          throw Error(filename + ": " + e.what());
        }
    }

    ParameterHandler first_pass;
    declare_parameters(first_pass, {}, {});
    parse_tolerantly(filename, first_pass);

    declare_parameters(prm,
                       Scene::segment_names(first_pass),
                       Planning::moved_segment_names(first_pass),
                       Scene::cut_names(first_pass),
                       PlanningList::plan_names(first_pass));
    prm.parse_input(filename);
  }

  void
  Simulator::print_default_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    declare_parameters(prm, {"fixed", "bone"}, {"bone"});
    prm.print_parameters(out, ParameterHandler::PRM);
  }
} // namespace softface

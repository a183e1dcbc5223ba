// The plannings a scene runs (core): its Planning section or a sweep of one
// motion quantity, and the further plans it lists; every model solves them
// in turn after one setup.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/planning_list.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softface
{
  void
  PlanningList::declare_parameters(
    ParameterHandler               &prm,
    const std::vector<std::string> &moved_segments,
    const std::vector<std::string> &plan_names)
  {
    Planning::declare_parameters(prm, moved_segments);
    prm.enter_subsection("Planning");
    prm.declare_entry(
      "Plannings",
      "",
      Patterns::List(Patterns::Anything()),
      "Further plans to solve after the Planning section's (or its sweep), "
      "each with a subsection 'Plan <name>' holding a 'Motion <segment>' "
      "subsection for each of the 'Moved segments' (the identity if "
      "omitted). Every model solves every plan after one setup; the table "
      "and summary.csv get one row per model and plan.");
    prm.declare_entry(
      "Response basis",
      "auto",
      Patterns::Selection("auto|always|never"),
      "For a model whose answer is linear in the motion (linear fem and "
      "mass tensor, without unilateral contact): 'always' solves once for "
      "each of the 12 entries of (R - I, t) of every moved segment (and "
      "once for the body force) and then computes every plan as their "
      "combination (exact to the solver's tolerance; ResponseBasis); "
      "'never' solves every plan; 'auto' builds the basis when the plans "
      "outnumber its solves.");
    for (const std::string &name : plan_names)
      {
        prm.enter_subsection("Plan " + name);
        Planning::declare_motion_entries(prm, moved_segments, false);
        prm.leave_subsection();
      }
    prm.enter_subsection("Sweep");
    prm.declare_entry("Segment",
                      "",
                      Patterns::Anything(),
                      "A moved segment whose motion is swept: the Planning "
                      "section's motions with one quantity of this "
                      "segment's set to each of 'Steps' values from 'From' "
                      "to 'To' in turn (replacing the Planning section's "
                      "plan). Empty: no sweep.");
    prm.declare_entry("Quantity",
                      "translation z",
                      Patterns::Selection("translation x|translation y|"
                                          "translation z|rotation angle"),
                      "The quantity swept: a component of the translation "
                      "(mm) or the rotation angle (degrees).");
    prm.declare_entry("From", "0", Patterns::Double(), "First value.");
    prm.declare_entry("To", "0", Patterns::Double(), "Last value.");
    prm.declare_entry("Steps",
                      "2",
                      Patterns::Integer(2, 1000),
                      "Number of plans, evenly spaced from 'From' to 'To'.");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  std::vector<std::string>
  PlanningList::plan_names(ParameterHandler &prm)
  {
    prm.enter_subsection("Planning");
    const auto names = Utilities::split_string_list(prm.get("Plannings"));
    prm.leave_subsection();
    return names;
  }

  void
  PlanningList::parse_parameters(ParameterHandler &prm, const Scene &scene)
  {
    plans.clear();
    prm.enter_subsection("Planning");
    const auto moved = Utilities::split_string_list(prm.get("Moved segments"));
    const std::string basis_name = prm.get("Response basis");
    basis                        = basis_name == "always" ? Basis::always :
                                   basis_name == "never"  ? Basis::never :
                                                            Basis::automatic;

    prm.enter_subsection("Sweep");
    const std::string  swept    = prm.get("Segment");
    const std::string  quantity = prm.get("Quantity");
    const double       from     = prm.get_double("From");
    const double       to       = prm.get_double("To");
    const unsigned int steps    = prm.get_integer("Steps");
    prm.leave_subsection();

    if (swept.empty())
      {
        NamedPlanning plan{"planning", {}};
        plan.planning.parse_motions(prm, scene, moved, "Planning");
        plans.push_back(plan);
      }
    else
      {
        if (std::find(moved.begin(), moved.end(), swept) == moved.end())
          throw Error("Planning/Sweep: 'Segment' is '" + swept +
                      "', which is not one of the 'Moved segments'.");
        if (from == to)
          throw Error("Planning/Sweep: 'From' and 'To' are equal: every "
                      "plan of the sweep would be the same.");
        for (unsigned int i = 0; i < steps; ++i)
          {
            double value = from + (to - from) * i / (steps - 1.);
            // 0 rather than a rounding residue in the plan's name.
            if (std::abs(value) <
                1e-12 * std::max(std::abs(from), std::abs(to)))
              value = 0.;
            std::ostringstream name;
            name << swept << ' ' << quantity << ' ' << value;
            NamedPlanning plan{name.str(), {}};
            plan.planning.parse_motions(
              prm,
              scene,
              moved,
              "Planning (Sweep '" + name.str() + "')",
              [&](const std::string &segment, Planning::MotionEntries &e) {
                if (segment != swept)
                  return;
                if (quantity == "rotation angle")
                  e.angle_in_degrees = value;
                else
                  e.translation[quantity.back() - 'x'] = value;
              });
            plans.push_back(plan);
          }
      }

    for (const std::string &name :
         Utilities::split_string_list(prm.get("Plannings")))
      {
        for (const auto &plan : plans)
          if (plan.name == name)
            throw Error("Planning/Plannings: the plan name '" + name +
                        "' is used twice.");
        NamedPlanning plan{name, {}};
        prm.enter_subsection("Plan " + name);
        plan.planning.parse_motions(prm, scene, moved, "Planning/Plan " + name);
        prm.leave_subsection();
        plans.push_back(plan);
      }
    prm.leave_subsection();
    // Names label rows and files: a sweep's steps too close to print apart
    // would overwrite each other.
    for (unsigned int p = 1; p < plans.size(); ++p)
      for (unsigned int q = 0; q < p; ++q)
        if (plans[p].name == plans[q].name)
          throw Error("Planning: two plans are named '" + plans[p].name +
                      "' (a Sweep's values must differ in their first 6 "
                      "digits).");
  }
} // namespace softface

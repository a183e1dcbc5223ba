#ifndef softface_planning_list_h
#define softface_planning_list_h

#include <deal.II/base/parameter_handler.h>

#include <softface/core/planning.h>
#include <softface/core/scene.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The plannings a scene runs, in order: its Planning section, or a sweep
   * of one quantity of it (a moved segment's translation along an axis or
   * its rotation angle, over a range in N steps), followed by every plan
   * listed in "Planning/Plannings" (a subsection "Plan <name>" each, with
   * the same "Motion <segment>" entries). Every model solves them in turn
   * after one setup.
   */
  class PlanningList
  {
  public:
    /// How a model linear in the motion re-plans (ResponseBasis).
    enum class Basis
    {
      automatic,
      always,
      never
    };

    struct NamedPlanning
    {
      /// "planning" for the Planning section alone; else the plan's name
      std::string name;
      Planning    planning;
    };

    /**
     * The Planning section (Planning::declare_parameters) with the list of
     * further plans, one subsection "Plan <name>" for each name in
     * @p plan_names, the Sweep and the response basis.
     */
    static void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &moved_segments,
                       const std::vector<std::string> &plan_names);

    /// The names listed in "Planning/Plannings" of a parsed handler.
    static std::vector<std::string>
    plan_names(ParameterHandler &prm);

    /// Throws a clear error on a sweep or plan the scene cannot take.
    void
    parse_parameters(ParameterHandler &prm, const Scene &scene);

    std::vector<NamedPlanning> plans;
    Basis                      basis = Basis::automatic;
  };
} // namespace softface

#endif

#ifndef softface_planning_h
#define softface_planning_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <softface/core/rigid_motion.h>
#include <softface/core/scene.h>

#include <map>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The surgeon's plan: a rigid motion for each moved bone segment; every
   * other segment stays where it is. It turns into the prescribed
   * displacement of the join points that every model takes.
   */
  class Planning
  {
  public:
    /// One subsection "Motion <name>" for each name in @p moved_segments.
    static void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &moved_segments);

    /// The names listed in "Planning/Moved segments" of a parsed handler.
    static std::vector<std::string>
    moved_segment_names(ParameterHandler &prm);

    /// Throws a clear error if a moved segment is not one of the scene's.
    void
    parse_parameters(ParameterHandler &prm, const Scene &scene);

    void
    set_motion(const unsigned int segment, const RigidMotion &motion);

    /// The motion of @p segment (the identity for a segment not moved).
    RigidMotion
    motion(const unsigned int segment) const;

    /**
     * The displacement of every join point under this plan, as a vector on
     * the scene's DoF layout (zero on the free DoFs but those of a vertex
     * sliding on a bone: the bone's displacement there); with @p load < 1,
     * under each motion's fraction @p load (RigidMotion::fraction()).
     */
    Vector<double>
    prescribed_displacement(const Scene &scene, const double load = 1.) const;

  private:
    std::map<unsigned int, RigidMotion> motion_of_segment;
  };
} // namespace softface

#endif

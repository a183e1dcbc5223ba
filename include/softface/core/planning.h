#ifndef softface_planning_h
#define softface_planning_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <softface/core/rigid_motion.h>
#include <softface/core/scene.h>

#include <functional>
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

    /**
     * The subsections "Motion <name>" alone, in the handler's current
     * subsection (a further plan's, PlanningList); every motion the
     * identity by default unless @p default_lift (the main planning: the
     * bone lifted 6 mm).
     */
    static void
    declare_motion_entries(ParameterHandler               &prm,
                           const std::vector<std::string> &moved_segments,
                           const bool                      default_lift);

    /// A motion's entries as read, before it becomes a RigidMotion.
    struct MotionEntries
    {
      Tensor<1, 3> translation;
      Tensor<1, 3> axis;
      double       angle_in_degrees = 0.;
      std::string  centre; ///< "x, y, z", or empty: the join centroid
    };
    /// Changes a segment's entries before they are used (a sweep).
    using Adjustment =
      std::function<void(const std::string &segment, MotionEntries &entries)>;

    /// The names listed in "Planning/Moved segments" of a parsed handler.
    static std::vector<std::string>
    moved_segment_names(ParameterHandler &prm);

    /// Throws a clear error if a moved segment is not one of the scene's.
    void
    parse_parameters(ParameterHandler &prm, const Scene &scene);

    /**
     * Read the motions of @p moved_segments from the "Motion <name>"
     * subsections of the handler's current subsection, each changed by
     * @p adjust if given; @p where names that subsection in errors.
     */
    void
    parse_motions(ParameterHandler               &prm,
                  const Scene                    &scene,
                  const std::vector<std::string> &moved_segments,
                  const std::string              &where,
                  const Adjustment               &adjust = {});

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

    /// The segments this plan moves, in increasing order.
    std::vector<unsigned int>
    moved_segments() const;

    /**
     * A displacement of the join points given per segment, as a vector on
     * the scene's DoF layout (see prescribed_displacement()):
     * @p displacement(segment, x) at every join point x of each segment in
     * @p segments and at every vertex that slides on such a segment's
     * bone; zero elsewhere.
     */
    static Vector<double>
    join_displacement(
      const Scene                                          &scene,
      const std::vector<unsigned int>                      &segments,
      const std::function<Tensor<1, 3>(const unsigned int segment,
                                       const Point<3>    &x)> &displacement);

  private:
    std::map<unsigned int, RigidMotion> motion_of_segment;
  };
} // namespace softface

#endif

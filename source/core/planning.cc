// The surgeon's plan (core): a rigid motion per moved bone segment from the
// parameter file, and the join points' prescribed displacement it gives on the
// shared DoF layout; the input of every model's solve.

#include <cmath>

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/planning.h>

namespace softface
{
  namespace
  {
    Tensor<1, 3>
    parse_vector(const std::string &text)
    {
      const auto   entries = Utilities::split_string_list(text);
      Tensor<1, 3> v;
      for (unsigned int d = 0; d < 3; ++d)
        v[d] = Utilities::string_to_double(entries[d]);
      return v;
    }
  } // namespace

  void
  Planning::declare_parameters(ParameterHandler               &prm,
                               const std::vector<std::string> &moved_segments)
  {
    prm.enter_subsection("Planning");
    prm.declare_entry("Moved segments",
                      "bone",
                      Patterns::List(Patterns::Anything()),
                      "Bone segments that the surgeon moves, each with a "
                      "subsection 'Motion <name>'. Segments not listed stay "
                      "where they are (their join points do not move).");
    declare_motion_entries(prm, moved_segments, true);
    prm.leave_subsection();
  }

  void
  Planning::declare_motion_entries(
    ParameterHandler               &prm,
    const std::vector<std::string> &moved_segments,
    const bool                      default_lift)
  {
    const auto vector3 = Patterns::List(Patterns::Double(), 3, 3);
    for (const std::string &name : moved_segments)
      {
        prm.enter_subsection("Motion " + name);
        prm.declare_entry("Translation",
                          default_lift && name == "bone" ? "0, 0, 6" :
                                                           "0, 0, 0",
                          vector3,
                          "Translation t in mm, applied after the rotation: "
                          "x -> R (x - c) + c + t.");
        prm.declare_entry("Rotation axis",
                          "0, 0, 1",
                          vector3,
                          "Axis of the rotation R (any length but zero).");
        prm.declare_entry("Rotation angle",
                          "0",
                          Patterns::Double(-360., 360.),
                          "Angle of the rotation R in degrees "
                          "(right-handed about the axis).");
        prm.declare_entry("Rotation centre",
                          "",
                          Patterns::Anything(),
                          "Centre c of the rotation in mm as 'x, y, z'; empty "
                          "means the centroid of the segment's join points.");
        prm.leave_subsection();
      }
  }

  std::vector<std::string>
  Planning::moved_segment_names(ParameterHandler &prm)
  {
    prm.enter_subsection("Planning");
    const auto names = Utilities::split_string_list(prm.get("Moved segments"));
    prm.leave_subsection();
    return names;
  }

  void
  Planning::parse_parameters(ParameterHandler &prm, const Scene &scene)
  {
    prm.enter_subsection("Planning");
    const auto names = Utilities::split_string_list(prm.get("Moved segments"));
    parse_motions(prm, scene, names, "Planning");
    prm.leave_subsection();
  }

  void
  Planning::parse_motions(ParameterHandler               &prm,
                          const Scene                    &scene,
                          const std::vector<std::string> &moved_segments,
                          const std::string              &where,
                          const Adjustment               &adjust)
  {
    motion_of_segment.clear();
    for (const std::string &name : moved_segments)
      {
        const std::string motion_where = where + "/Motion " + name;
        unsigned int      segment;
        try
          {
            segment = scene.segment_index(name);
          }
        catch (const Error &e)
          {
            throw Error("Planning: 'Moved segments' names a segment the "
                        "scene does not have. " +
                        std::string(e.what()));
          }

        prm.enter_subsection("Motion " + name);
        MotionEntries entries;
        entries.translation      = parse_vector(prm.get("Translation"));
        entries.axis             = parse_vector(prm.get("Rotation axis"));
        entries.angle_in_degrees = prm.get_double("Rotation angle");
        entries.centre           = prm.get("Rotation centre");
        prm.leave_subsection();
        if (adjust)
          adjust(name, entries);

        Point<3>          centre;
        const std::string centre_text = entries.centre;
        if (!centre_text.empty())
          {
            const auto parts = Utilities::split_string_list(centre_text);
            if (parts.size() != 3)
              throw Error(motion_where +
                          ": 'Rotation centre' must be empty or 'x, y, z' "
                          "(got '" +
                          centre_text + "').");
            try
              {
                centre = Point<3>(parse_vector(centre_text));
              }
            catch (const std::exception &)
              {
                throw Error(motion_where +
                            ": 'Rotation centre' is not three numbers (got '" +
                            centre_text + "').");
              }
            // strtod reads "nan" and "inf", which the other vectors'
            // patterns refuse.
            for (unsigned int d = 0; d < 3; ++d)
              if (!std::isfinite(centre[d]))
                throw Error(motion_where +
                            ": 'Rotation centre' must be finite (got '" +
                            centre_text + "').");
          }
        else
          {
            // The mean of the segment's join points as the scene first
            // found them (before an effect freed some).
            const auto &c = scene.segments[segment].join_centroid;
            if (c.size() != 3)
              throw Error(motion_where +
                          ": the segment has no join point to take the "
                          "'Rotation centre' from; give one.");
            centre = Point<3>(c[0], c[1], c[2]);
          }
        try
          {
            set_motion(segment,
                       RigidMotion(entries.translation,
                                   entries.axis,
                                   entries.angle_in_degrees,
                                   centre));
          }
        catch (const Error &e)
          {
            throw Error(motion_where + ": " + e.what());
          }
      }
  }

  void
  Planning::set_motion(const unsigned int segment, const RigidMotion &motion)
  {
    motion_of_segment[segment] = motion;
  }

  RigidMotion
  Planning::motion(const unsigned int segment) const
  {
    const auto m = motion_of_segment.find(segment);
    return m == motion_of_segment.end() ? RigidMotion() : m->second;
  }

  std::vector<unsigned int>
  Planning::moved_segments() const
  {
    std::vector<unsigned int> segments;
    for (const auto &[segment, motion] : motion_of_segment)
      segments.push_back(segment);
    return segments;
  }

  Vector<double>
  Planning::prescribed_displacement(const Scene &scene, const double load) const
  {
    // Each motion a fraction of the way: the bones stay rigid.
    auto motions = motion_of_segment;
    if (load != 1.)
      for (auto &[segment, motion] : motions)
        motion = motion.fraction(load);
    return join_displacement(scene,
                             moved_segments(),
                             [&motions](const unsigned int segment,
                                        const Point<3>    &x) {
                               return motions.at(segment).displacement(x);
                             });
  }

  Vector<double>
  Planning::join_displacement(
    const Scene                                          &scene,
    const std::vector<unsigned int>                      &segments,
    const std::function<Tensor<1, 3>(const unsigned int segment,
                                     const Point<3>    &x)> &displacement)
  {
    std::vector<bool> moved(scene.segments.size(), false);
    for (const unsigned int s : segments)
      moved[s] = true;
    const auto is_moved = [&moved](const unsigned int segment) {
      return segment < moved.size() && moved[segment];
    };
    Vector<double> u(scene.n_dofs());
    const auto    &vertices = scene.vertices();
    for (unsigned int v = 0; v < vertices.size(); ++v)
      {
        const unsigned int segment = scene.vertex_segment()[v];
        if (!is_moved(segment) ||
            scene.vertex_dofs()[v][0] == numbers::invalid_dof_index)
          continue;
        const Tensor<1, 3> d = displacement(segment, vertices[v]);
        for (unsigned int c = 0; c < 3; ++c)
          u[scene.vertex_dofs()[v][c]] = d[c];
      }
    // A vertex sliding on a bone surface: the bone's displacement there,
    // which places the surface (SceneEffects::free_vertex_constraints).
    for (const auto &constraint : scene.effects.vertex_constraints)
      {
        if (!is_moved(constraint.segment))
          continue;
        const Tensor<1, 3> d =
          displacement(constraint.segment, vertices[constraint.vertex]);
        for (unsigned int c = 0; c < 3; ++c)
          u[scene.vertex_dofs()[constraint.vertex][c]] = d[c];
      }
    return u;
  }
} // namespace softface

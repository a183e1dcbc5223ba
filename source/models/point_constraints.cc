// The scene's vertex constraints on the points of the point models. See
// models/point_constraints.h.

#include <softface/models/point_constraints.h>

namespace softface
{
  void
  make_point_constraints(const Scene                  &scene,
                         const unsigned int            n_points,
                         std::vector<PointConstraint> &constraints,
                         std::vector<int>             &constraint_of_point)
  {
    constraints.clear();
    constraint_of_point.clear();
    if (scene.has_vertex_constraints())
      constraint_of_point.assign(n_points, -1);
    for (const VertexConstraint &c : scene.effects.vertex_constraints)
      {
        const unsigned int a   = scene.vertex_dofs()[c.vertex][0] / 3;
        const unsigned int b   = c.partner == numbers::invalid_unsigned_int ?
                                   a :
                                   scene.vertex_dofs()[c.partner][0] / 3;
        constraint_of_point[a] = constraint_of_point[b] = constraints.size();
        constraints.push_back({a, b, c.normal / c.normal.norm(), c.unilateral});
      }
  }
} // namespace softface

// Figures of displacement fields on the shared layout (core): largest
// displacement and max/mean distance between two fields over the free
// vertices.

#include <softface/core/displacement.h>

#include <algorithm>
#include <cmath>

namespace softface
{
  namespace Displacement
  {
    double
    max_norm(const Scene &scene, const Vector<double> &u)
    {
      double max = 0.;
      for (const auto &dofs : scene.vertex_dofs())
        if (dofs[0] != numbers::invalid_dof_index)
          max = std::max(max,
                         std::sqrt(u[dofs[0]] * u[dofs[0]] +
                                   u[dofs[1]] * u[dofs[1]] +
                                   u[dofs[2]] * u[dofs[2]]));
      return max;
    }

    Difference
    free_vertex_difference(const Scene          &scene,
                           const Vector<double> &a,
                           const Vector<double> &b)
    {
      Difference   result;
      double       sum = 0.;
      unsigned int n   = 0;
      for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
        {
          const auto &dofs = scene.vertex_dofs()[v];
          if (dofs[0] == numbers::invalid_dof_index ||
              scene.vertex_segment()[v] != numbers::invalid_unsigned_int)
            continue;
          double d = 0.;
          for (const auto dof : dofs)
            d += (a[dof] - b[dof]) * (a[dof] - b[dof]);
          d          = std::sqrt(d);
          result.max = std::max(result.max, d);
          sum += d;
          ++n;
        }
      result.mean = n ? sum / n : 0.;
      return result;
    }
  } // namespace Displacement
} // namespace softface

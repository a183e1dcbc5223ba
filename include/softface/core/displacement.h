#ifndef softface_core_displacement_h
#define softface_core_displacement_h

#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>

namespace softface
{
  using namespace dealii;

  /**
   * Figures of displacement fields on the shared layout, whichever model
   * computed them: the largest displacement, and how far one field is from
   * another over the free vertices (the table's comparison with the
   * reference model, the mass tensor model's precision).
   */
  namespace Displacement
  {
    /// Largest |u| over the vertices, mm.
    double
    max_norm(const Scene &scene, const Vector<double> &u);

    struct Difference
    {
      double max  = 0.; ///< mm
      double mean = 0.; ///< mm
    };

    /// max and mean of |a - b| over the free vertices.
    Difference
    free_vertex_difference(const Scene          &scene,
                           const Vector<double> &a,
                           const Vector<double> &b);
  } // namespace Displacement
} // namespace softface

#endif

#ifndef softface_rigid_motion_h
#define softface_rigid_motion_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

namespace softface
{
  using namespace dealii;

  /**
   * The planned motion of a bone segment (seed 3.3): x -> R (x - c) + c + t,
   * with R the rotation by an angle about an axis through the centre c.
   */
  class RigidMotion
  {
  public:
    /// The identity (a fixed segment).
    RigidMotion();
    RigidMotion(const Tensor<1, 3> &translation,
                const Tensor<1, 3> &axis,
                const double        angle_in_degrees,
                const Point<3>     &centre);

    Point<3>
    operator()(const Point<3> &x) const;
    Tensor<1, 3>
    displacement(const Point<3> &x) const;

  private:
    Tensor<2, 3> rotation;
    Point<3>     centre;
    Tensor<1, 3> translation;
  };
} // namespace softface

#endif

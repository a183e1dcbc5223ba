#ifndef softface_rigid_motion_h
#define softface_rigid_motion_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

namespace softface
{
  using namespace dealii;

  /**
   * The planned motion of a bone segment (Mollemans et al. 2007, Sec. 3.3):
   * x -> R (x - c) + c + t, with R the rotation by an angle about an axis
   * through the centre c.
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

    /**
     * The motion a fraction @p s of the way: the rotation by s times the
     * angle about the same axis and centre, and s times the translation.
     * Every fraction is rigid, unlike s times the displacement, which
     * shrinks a rotated bone on the way (half-way through a turn by theta,
     * a distance across the axis by the factor cos(theta / 2)): the
     * nonlinear models' load path (Models::Interface).
     */
    RigidMotion
    fraction(const double s) const;

  private:
    Tensor<1, 3> axis{{0., 0., 1.}};
    double       angle_in_degrees = 0.;
    Tensor<2, 3> rotation;
    Point<3>     centre;
    Tensor<1, 3> translation;
  };
} // namespace softface

#endif

// A bone segment's planned motion x -> R (x - c) + c + t (core; Mollemans et
// al. 2007, Sec. 3.3).

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/physics/transformations.h>

#include <softface/core/error.h>
#include <softface/core/rigid_motion.h>

#include <cmath>

namespace softface
{
  RigidMotion::RigidMotion()
      : rotation(Tensor<2, 3>(unit_symmetric_tensor<3>()))
  {}

  RigidMotion::RigidMotion(const Tensor<1, 3> &translation,
                           const Tensor<1, 3> &axis,
                           const double        angle_in_degrees,
                           const Point<3>     &centre)
      : angle_in_degrees(angle_in_degrees)
      , rotation(Tensor<2, 3>(unit_symmetric_tensor<3>()))
      , centre(centre)
      , translation(translation)
  {
    if (angle_in_degrees != 0.)
      {
        if (!(axis.norm() > 0.))
          throw Error("A rotation by " + std::to_string(angle_in_degrees) +
                      " degrees needs a non-zero rotation axis.");
        this->axis = axis / axis.norm();
        rotation   = Physics::Transformations::Rotations::rotation_matrix_3d(
          this->axis, angle_in_degrees * M_PI / 180.);
      }
  }

  RigidMotion
  RigidMotion::fraction(const double s) const
  {
    return RigidMotion(s * translation, axis, s * angle_in_degrees, centre);
  }

  Point<3>
  RigidMotion::operator()(const Point<3> &x) const
  {
    return centre + rotation * (x - centre) + translation;
  }

  Tensor<1, 3>
  RigidMotion::displacement(const Point<3> &x) const
  {
    return (*this)(x)-x;
  }
} // namespace softface

#ifndef softface_models_point_constraints_h
#define softface_models_point_constraints_h

#include <deal.II/base/tensor.h>

#include <softface/core/scene.h>

#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * A scene's vertex constraint (sliding contact, separated lips) as the
   * point models (mass tensor, mass spring) read it: on points (the vertex
   * whose DoFs are 3p, 3p+1, 3p+2, see PointMesh), with a unit normal.
   */
  struct PointConstraint
  {
    /// The point and its partner (b = a without one: a sliding point).
    unsigned int a, b;
    Tensor<1, 3> n;
    bool         unilateral;
  };

  /**
   * The vertex constraints of @p scene into @p constraints, and for each of
   * its @p n_points points the index of its constraint in
   * @p constraint_of_point, or -1. Without constraints both stay empty, so
   * that a sweep's test of a point is one branch on an empty vector.
   */
  void
  make_point_constraints(const Scene                  &scene,
                         const unsigned int            n_points,
                         std::vector<PointConstraint> &constraints,
                         std::vector<int>             &constraint_of_point);
} // namespace softface

#endif

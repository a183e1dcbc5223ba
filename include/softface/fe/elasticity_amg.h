#ifndef softface_elasticity_amg_h
#define softface_elasticity_amg_h

#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <softface/core/scene.h>

namespace softface
{
  using namespace dealii;

  /**
   * Trilinos ML smoothed aggregation for an elasticity matrix on the scene's
   * DoF layout, given the six rigid-body modes as near-null space (deal.II
   * 9.4 hands ML only the translations) and aggregating vertices, not single
   * DoFs. Shared by the linear and the nonlinear FEM models.
   */
  void
  initialize_elasticity_amg(const Scene                          &scene,
                            const TrilinosWrappers::SparseMatrix &matrix,
                            const double       aggregation_threshold,
                            const unsigned int smoother_sweeps,
                            TrilinosWrappers::PreconditionAMG &amg);

  /**
   * The same for any layout of a three-component field, given every DoF's
   * support point and component (e.g. the quadratic reference solution).
   */
  void
  initialize_elasticity_amg(const std::vector<Point<3>>          &dof_points,
                            const std::vector<unsigned int>      &dof_component,
                            const TrilinosWrappers::SparseMatrix &matrix,
                            const double       aggregation_threshold,
                            const unsigned int smoother_sweeps,
                            TrilinosWrappers::PreconditionAMG &amg);
} // namespace softface

#endif

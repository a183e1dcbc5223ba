#ifndef softface_hyperelasticity_h
#define softface_hyperelasticity_h

#include <deal.II/base/quadrature.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <softface/fe/linear_elasticity.h>

#include <array>
#include <string>

namespace softface
{
  using namespace dealii;

  /**
   * Large-deformation elasticity on P1 tetrahedra (seed 2.1, "the full
   * Green-Lagrange tensor"): the deformation gradient F = I + grad u is
   * constant per tetrahedron, so the nodal forces f_a = V P(F) grad N_a and
   * their derivatives (the consistent tangent) have closed forms.
   */
  namespace Hyperelasticity
  {
    enum class Law
    {
      /// S = lambda tr(E) I + 2 mu E with E = (F^T F - I) / 2: what
      /// CalculiX solves for *ELASTIC with NLGEOM; softens under strong
      /// compression.
      st_venant_kirchhoff,
      /// W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2: stiffens under
      /// compression, so it can follow motions that crush tissue.
      neo_hooke,
      /// Hooke's law in the small-strain measure eps = sym(F - I), the
      /// linear FEM model's equations: one Newton iteration solves them.
      /// With quadratic tetrahedra it gives linear FEM on the reference's
      /// discretisation, which separates linear elasticity's model error
      /// from P1's discretisation error. Never refuses a tetrahedron.
      linear
    };

    /// "st venant-kirchhoff", "neo-hooke" or "linear".
    Law
    law_from_name(const std::string &name);

    /// The inverse of law_from_name().
    std::string
    law_name(const Law law);

    /// What one tetrahedron contributes at a displacement.
    struct CellResponse
    {
      double                                 energy = 0.;
      std::array<Tensor<1, 3>, 4>            force;   ///< f_a = V P grad N_a
      LinearElasticity::TetrahedronStiffness tangent; ///< d f_a / d u_b
    };

    /**
     * Forces (and, if @p with_tangent, the tangent) of a tetrahedron with
     * reference shape gradients @p grad and volume @p volume at vertex
     * displacements @p u. Returns false, leaving @p response unspecified,
     * if det F <= 0 (the tetrahedron is inverted) and the law is not
     * linear.
     */
    bool
    cell_response(const Law                          law,
                  const double                       lambda,
                  const double                       mu,
                  const std::array<Tensor<1, 3>, 4> &grad,
                  const double                       volume,
                  const std::array<Tensor<1, 3>, 4> &u,
                  const bool                         with_tangent,
                  CellResponse                      &response);

    /**
     * First Piola-Kirchhoff stress P(F) and, if @p A is not null, its
     * derivative A_iJkL = dP_iJ / dF_kL at one material point. Returns false
     * if det F <= 0.
     */
    bool
    material_response(const Law           law,
                      const double        lambda,
                      const double        mu,
                      const Tensor<2, 3> &F,
                      Tensor<2, 3>       &P,
                      Tensor<4, 3>       *A);

    /**
     * Nodal forces (and, if @p tangent is not null, the tangent, added into
     * it) of the displacement @p u on any vector-valued element of
     * @p dof_handler, by quadrature: what the quadratic reference solution
     * uses; on P1 it reproduces cell_response(). Returns false if det F <= 0
     * at a quadrature point.
     */
    bool
    assemble(const Law               law,
             const double            lambda,
             const double            mu,
             const Mapping<3>       &mapping,
             const DoFHandler<3>    &dof_handler,
             const Quadrature<3>    &quadrature,
             const Vector<double>   &u,
             Vector<double>         &forces,
             SparseMatrix<double>   *tangent);
  } // namespace Hyperelasticity
} // namespace softface

#endif

#ifndef softface_fe_material_law_h
#define softface_fe_material_law_h

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <softface/core/material.h>

#include <string>

namespace softface
{
  using namespace dealii;

  /**
   * The soft tissue's stress response, each law written once: the first
   * Piola-Kirchhoff stress P(F) and its derivative A = dP/dF at one material
   * point. Every elasticity kernel (the closed-form P1 forms in
   * fe/elasticity.h, quadrature on any element, the linear stiffness that
   * the linear FEM and mass tensor models read) contracts these with shape
   * gradients; none has a law of its own.
   */
  namespace MaterialLaw
  {
    enum class Law
    {
      /// Hooke's law in the small-strain measure eps = sym(F - I): the
      /// linear FEM model's equations (Mollemans et al. 2007, eqs. 6-10). Never
      /// refuses a deformation.
      linear,
      /// S = lambda tr(E) I + 2 mu E with E = (F^T F - I) / 2: the paper's
      /// large-deformation law and CalculiX's *ELASTIC with NLGEOM; softens
      /// under strong compression.
      st_venant_kirchhoff,
      /// W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2: stiffens under
      /// compression, so it can follow motions that crush tissue.
      neo_hooke
    };

    /// "linear", "st venant-kirchhoff" or "neo-hooke".
    Law
    from_name(const std::string &name);

    std::string
    name(const Law law);

    /// The names joined by '|', for a Patterns::Selection.
    std::string
    selection();

    /**
     * P(F) and, if @p A is not null, A_iJkL = dP_iJ / dF_kL. Returns false,
     * leaving the outputs unspecified, if det F <= 0 and the law is not
     * linear (the material point is inverted). At F = I every law's A is
     * the linear law's.
     */
    bool
    first_piola_kirchhoff(const Law           law,
                          const Lame         &lame,
                          const Tensor<2, 3> &F,
                          Tensor<2, 3>       &P,
                          Tensor<4, 3>       *A);
  } // namespace MaterialLaw
} // namespace softface

#endif

#ifndef softface_material_h
#define softface_material_h

#include <deal.II/base/parameter_handler.h>

namespace softface
{
  using namespace dealii;

  /// Lame coefficients of an isotropic material, N/mm^2 (MPa).
  struct Lame
  {
    double lambda = 0.;
    double mu     = 0.;
  };

  /**
   * Homogeneous isotropic soft tissue. Lengths in softface are in mm, so the
   * Lame coefficients are returned in N/mm^2 (MPa); the parameter file gives
   * Young's modulus in Pa because that is how tissue data are published.
   */
  class Material
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /// Young's modulus in N/mm^2.
    double
    youngs_modulus() const;
    /// seed eq. 6
    double
    lambda() const;
    /// seed eq. 7
    double
    mu() const;
    /// Both Lame coefficients.
    Lame
    lame() const;

    double youngs_modulus_pa = 3000.;
    double poissons_ratio    = 0.46;
  };
} // namespace softface

#endif

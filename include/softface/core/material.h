#ifndef softface_material_h
#define softface_material_h

#include <deal.II/base/parameter_handler.h>

#include <string>

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
    /// Mollemans et al. 2007, eq. 6
    double
    lambda() const;
    /// The paper's eq. 7
    double
    mu() const;
    /// Both Lame coefficients.
    Lame
    lame() const;

    /**
     * Young's moduli softface accepts, in Pa. Far outside this range the
     * stiffness and force norms of the solvers under- or overflow (at 1e-200
     * Pa CG's residual became NaN); tests/youngs_modulus_independence checks
     * that both ends give the answer of 3 kPa with every model.
     */
    static constexpr double min_youngs_modulus_pa = 1e-3;
    static constexpr double max_youngs_modulus_pa = 1e13;

    /// Throw softface::Error, naming @p where, unless @p E is in range.
    static void
    check_youngs_modulus(const double E, const std::string &where);

    double youngs_modulus_pa = 3000.;
    double poissons_ratio    = 0.46;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &youngs_modulus_pa &poissons_ratio;
    }
  };
} // namespace softface

#endif

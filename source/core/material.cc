// The homogeneous tissue (core): Young's modulus and Poisson's ratio from the
// parameter file, and the Lame coefficients every model derives from them
// (Mollemans et al. 2007, eqs. 6-7).

#include <softface/core/error.h>
#include <softface/core/material.h>

namespace softface
{
  void
  Material::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    prm.declare_entry(
      "Young's modulus",
      "3000",
      Patterns::Double(min_youngs_modulus_pa, max_youngs_modulus_pa),
      "Young's modulus of the soft tissue in Pa, in [1e-3, "
      "1e13]. With only "
      "prescribed displacements and homogeneous tissue the "
      "displacement does not depend on it (Mollemans et al. 2007, Sec. 3.4).");
    prm.declare_entry("Poisson's ratio",
                      "0.46",
                      Patterns::Double(0., 0.5),
                      "Poisson's ratio of the soft tissue, in [0, 0.5).");
    prm.leave_subsection();
  }

  void
  Material::check_youngs_modulus(const double E, const std::string &where)
  {
    if (!(E >= min_youngs_modulus_pa && E <= max_youngs_modulus_pa))
      throw Error(where + ": " + number_text(E) + " Pa is outside [" +
                  number_text(min_youngs_modulus_pa) + ", " +
                  number_text(max_youngs_modulus_pa) +
                  "] Pa, the range softface's solvers are checked in (soft "
                  "tissue is about 1e3 to 1e5 Pa).");
  }

  void
  Material::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    youngs_modulus_pa = prm.get_double("Young's modulus");
    poissons_ratio    = prm.get_double("Poisson's ratio");
    prm.leave_subsection();
    check_youngs_modulus(youngs_modulus_pa, "Material/Young's modulus");
    if (!(poissons_ratio < 0.5))
      throw Error("Material: Poisson's ratio must be below 0.5 (got " +
                  number_text(poissons_ratio) +
                  "); 0.5 is incompressible, which P1 elements lock on.");
  }

  double
  Material::youngs_modulus() const
  {
    return youngs_modulus_pa * 1e-6;
  }

  double
  Material::lambda() const
  {
    const double E = youngs_modulus(), nu = poissons_ratio;
    return nu * E / ((1. + nu) * (1. - 2. * nu));
  }

  double
  Material::mu() const
  {
    return youngs_modulus() / (2. * (1. + poissons_ratio));
  }

  Lame
  Material::lame() const
  {
    return {lambda(), mu()};
  }
} // namespace softface

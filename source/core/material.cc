// The homogeneous tissue (core): Young's modulus and Poisson's ratio from the
// parameter file, and the Lame coefficients every model derives from them
// (seed eqs. 6-7).

#include <softface/core/error.h>
#include <softface/core/material.h>

namespace softface
{
  void
  Material::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    prm.declare_entry("Young's modulus",
                      "3000",
                      Patterns::Double(0., Patterns::Double::max_double_value),
                      "Young's modulus of the soft tissue in Pa. With only "
                      "prescribed displacements and homogeneous tissue the "
                      "displacement does not depend on it (seed 3.4).");
    prm.declare_entry("Poisson's ratio",
                      "0.46",
                      Patterns::Double(0., 0.5),
                      "Poisson's ratio of the soft tissue, in [0, 0.5).");
    prm.leave_subsection();
  }

  void
  Material::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    youngs_modulus_pa = prm.get_double("Young's modulus");
    poissons_ratio    = prm.get_double("Poisson's ratio");
    prm.leave_subsection();
    if (!(youngs_modulus_pa > 0.))
      throw Error("Material: Young's modulus must be positive (got " +
                  std::to_string(youngs_modulus_pa) + " Pa).");
    if (!(poissons_ratio < 0.5))
      throw Error("Material: Poisson's ratio must be below 0.5 (got " +
                  std::to_string(poissons_ratio) +
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

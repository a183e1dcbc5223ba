// Gravity (effects): the tissue's weight as a body force, for every model
// (a load in both FEMs, the f_j of eq. 12 of Mollemans et al. 2007 in the mass
// tensor model, a nodal force in the mass spring model).

#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/core/tetrahedron.h>
#include <softface/core/vec3_parameter.h>
#include <softface/effects/interface.h>

#include <cmath>
#include <map>
#include <memory>
#include <sstream>

namespace softface
{
  namespace Effects
  {
    /**
     * The weight of the tissue, rho g per unit volume, as consistent P1 nodal
     * loads: a quarter of each tetrahedron's weight on each of its vertices
     * (exact for a constant body force). Units: density in kg/m^3 and g in
     * m/s^2, as published; softface works in mm and N, so the force per
     * mm^3 is rho g 1e-9 N. Unlike displacement loading, the answer depends
     * on the moduli's absolute values.
     */
    class Gravity : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry(
          "Gravity",
          "0, 0, -9.81",
          Patterns::Anything(),
          "The gravitational acceleration in m/s^2 in the scene's frame, "
          "'x, y, z'. The patient scenes' frame is the CT's (x to the "
          "patient's left, y to the back of the head, z up the body): the "
          "face seen upright is '0, 0, -9.81', lying on the back as in the "
          "scanner '0, 9.81, 0'. The mesh is the tissue at rest as imaged; "
          "gravity here is a load added to it.");
        prm.declare_entry("Density",
                          "1000",
                          Patterns::Anything(),
                          "Density in kg/m^3 of every material id not listed "
                          "in 'Densities' (soft tissue is close to water).");
        prm.declare_entry(
          "Densities",
          "",
          Patterns::Anything(),
          "Density in kg/m^3 per material id, 'id: value, ...' (e.g. '1: "
          "1100, 2: 920, 3: 1060' for skin, fat and muscle).");
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        const auto   g = parse_vec3(prm.get("Gravity"), "Gravity");
        Tensor<1, 3> gravity;
        for (unsigned int d = 0; d < 3; ++d)
          gravity[d] = g[d];
        const auto densities =
          parse_material_values("Densities", prm.get("Densities"));
        const std::string density_text = prm.get("Density");
        char             *end          = nullptr;
        const double      density = std::strtod(density_text.c_str(), &end);
        if (density_text.empty() || *end != '\0' || !std::isfinite(density))
          throw Error("Density: '" + density_text + "' is not a number.");
        if (density < 0.)
          throw Error("Density: " + density_text +
                      " kg/m^3 is negative; a density must be >= 0.");
        for (const auto &[id, rho] : densities)
          if (rho < 0.)
            throw Error("Densities: material id " + std::to_string(id) +
                        " has a density of " + Utilities::to_string(rho) +
                        " kg/m^3; a density must be >= 0.");
        // Far beyond any tissue (osmium: 22,590 kg/m^3) or any posture
        // (100 g): a typo in units that would overflow the solvers.
        const auto too_dense = [](const double rho) { return rho > 1e5; };
        bool       dense     = too_dense(density);
        for (const auto &entry : densities)
          dense |= too_dense(entry.second);
        if (dense)
          throw Error("Density/Densities: a density above 100000 kg/m^3 is "
                      "not a tissue's (densities are in kg/m^3).");
        if (gravity.norm() > 1000.)
          throw Error("Gravity: |g| = " + Utilities::to_string(gravity.norm()) +
                      " m/s^2 is over 100 g (gravity is in m/s^2).");
        // kg/m^3 times mm^3 is 1e-9 kg.
        weight->gravity = gravity;
        weight->density_of_material_id.clear();
        for (const auto &[id, rho] : densities)
          weight->density_of_material_id[id] = rho * 1e-9;
        weight->density_otherwise = density * 1e-9;
      }

      unsigned int
      contributions() const override
      {
        return SceneEffects::body_forces;
      }

      void
      declare_rules(Scene &scene) const override
      {
        scene.effects.body_force_rules.push_back(weight);
      }

    protected:
      std::string
      check_and_add(Scene &scene) const override
      {
        double mass = 0.;
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          mass += weight->mass(cell);
        std::ostringstream line;
        line << "gravity: (" << weight->gravity << ") m/s^2, tissue mass "
             << mass << " kg, weight " << mass * weight->gravity.norm() << " N";
        return line.str();
      }

    private:
      /// The rule: a cell's mass times g.
      struct Weight : BodyForce
      {
        Tensor<1, 3> gravity;
        /// Mass per unit volume (kg/mm^3) of each listed material id and of
        /// any other.
        std::map<types::material_id, double> density_of_material_id;
        double                               density_otherwise = 0.;

        double
        mass_density(const types::material_id id) const
        {
          const auto listed = density_of_material_id.find(id);
          return listed != density_of_material_id.end() ? listed->second :
                                                          density_otherwise;
        }
        double
        mass(const Triangulation<3>::active_cell_iterator &cell) const
        {
          return mass_density(cell->material_id()) *
                 Tetrahedron::signed_volume(Tetrahedron::vertices(cell));
        }
        Tensor<1, 3>
        per_unit_volume(
          const Triangulation<3>::active_cell_iterator &cell) const override
        {
          return mass_density(cell->material_id()) * gravity;
        }
        Tensor<1, 3>
        on_cell(
          const Triangulation<3>::active_cell_iterator &cell) const override
        {
          return mass(cell) * gravity;
        }
      };
      std::shared_ptr<Weight> weight = std::make_shared<Weight>();
    };

    SOFTFACE_REGISTER_EFFECT(Gravity,
                             "gravity",
                             "The tissue's weight (density per material id, "
                             "gravity in the scene's frame) as a body force, "
                             "in every model.")
  } // namespace Effects
} // namespace softface

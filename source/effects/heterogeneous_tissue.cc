// Heterogeneous tissue (effects): Young's modulus and Poisson's ratio per
// material id (the mesh's tissue labels), for every model: the FEM element
// matrices and nonlinear laws, the mass tensor model's tensors and the mass
// spring model's spring constants (Gelder's formula per cell).

#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/effects/interface.h>

#include <map>
#include <memory>
#include <set>
#include <sstream>

namespace softface
{
  namespace Effects
  {
    /**
     * Tissues per material id. Every material id of the mesh gets one,
     * except those of bone segments (cells inside bone touch only join
     * points, whose motion is prescribed): they keep Scene::material. With
     * displacement loading only the ratios of the moduli matter; with
     * gravity the values do (in Pa, like Material).
     */
    class HeterogeneousTissue : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry(
          "Young's moduli",
          "1: 15000, 2: 3000, 3: 6000",
          Patterns::Anything(),
          "Young's modulus in Pa per material id, 'id: value, ...'. Every "
          "material id of the mesh outside bone must be listed. The default "
          "is for the patient meshes' labels (1 skin, 2 fat, 3 muscle): skin "
          "stiffer than muscle stiffer than fat, fat at the "
          "homogeneous 3000 Pa of Mollemans et al. 2007; published values "
          "spread over an order of "
          "magnitude and more (see doc/effects.md), so set your own.");
        prm.declare_entry(
          "Poisson's ratios",
          "",
          Patterns::Anything(),
          "Poisson's ratio per material id, 'id: value, ...', each in [0, "
          "0.5); an id not listed takes Material/Poisson's ratio.");
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        youngs_moduli =
          parse_material_values("Young's moduli", prm.get("Young's moduli"));
        poissons_ratios = parse_material_values("Poisson's ratios",
                                                prm.get("Poisson's ratios"));
        if (youngs_moduli.empty())
          throw Error("Young's moduli: no material id is listed.");
        for (const auto &[id, E] : youngs_moduli)
          Material::check_youngs_modulus(E,
                                         "Young's moduli: material id " +
                                           std::to_string(id));
        for (const auto &[id, nu] : poissons_ratios)
          {
            if (!(nu >= 0. && nu < 0.5))
              throw Error("Poisson's ratios: material id " +
                          std::to_string(id) + " has a ratio of " +
                          Utilities::to_string(nu) +
                          "; it must lie in [0, 0.5).");
            // A ratio without a modulus would be silently ignored.
            if (youngs_moduli.count(id) == 0)
              throw Error("Poisson's ratios: material id " +
                          std::to_string(id) +
                          " has no Young's modulus in 'Young's moduli'.");
          }
        // Tissue 0 is Material's (bone cells): 255 listed tissues at most.
        if (youngs_moduli.size() > 255)
          throw Error("Young's moduli: at most 255 material ids can be "
                      "listed (got " +
                      std::to_string(youngs_moduli.size()) + ").");
      }

      unsigned int
      contributions() const override
      {
        return SceneEffects::cell_materials;
      }

      void
      declare_rules(Scene &scene) const override
      {
        // Tissue 0 is Scene::material (bone cells); one per listed id.
        std::vector<Material> tissues = {scene.material};
        auto                  rule    = std::make_shared<TissueOfMaterialId>();
        for (const auto &segment : scene.segments)
          for (const auto id : segment.material_ids)
            rule->tissue_of_id[id] = 0;
        for (const auto &[id, E] : youngs_moduli)
          {
            Material tissue          = scene.material;
            tissue.youngs_modulus_pa = E;
            if (poissons_ratios.count(id))
              tissue.poissons_ratio = poissons_ratios.at(id);
            rule->tissue_of_id[id] = tissues.size();
            tissues.push_back(tissue);
          }
        scene.effects.tissues     = std::move(tissues);
        scene.effects.tissue_rule = std::move(rule);
      }

    protected:
      std::string
      check_and_add(Scene &scene) const override
      {
        std::set<types::material_id> bone;
        for (const auto &segment : scene.segments)
          bone.insert(segment.material_ids.begin(), segment.material_ids.end());
        // The cells of each id: their number, and the first one.
        std::map<
          types::material_id,
          std::pair<unsigned int, Triangulation<3>::active_cell_iterator>>
          cells_of_id;
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          {
            const auto id = cell->material_id();
            if (youngs_moduli.count(id) == 0 && bone.count(id) == 0)
              {
                std::ostringstream m;
                m << "Effects/heterogeneous tissue: material id " << int(id)
                  << " of the mesh ("
                  << Mesh::cell_description(scene.cell_name,
                                            cell->active_cell_index())
                  << " at (" << cell->center()
                  << ")) has no Young's modulus; list it in 'Young's "
                     "moduli'.";
                throw Error(m.str());
              }
            auto &[count, first] = cells_of_id[id];
            if (count++ == 0)
              first = cell;
          }

        std::ostringstream line;
        line << "heterogeneous tissue:";
        for (const auto &[id, cells] : cells_of_id)
          if (youngs_moduli.count(id))
            {
              const Material &tissue =
                scene.effects.tissues[scene.effects.tissue(cells.second)];
              line << " id " << int(id) << " E " << tissue.youngs_modulus_pa
                   << " Pa nu " << tissue.poissons_ratio << " (" << cells.first
                   << " cells);";
            }
          else
            line << " id " << int(id) << " bone (" << cells.first << " cells);";
        std::string text = line.str();
        text.pop_back();
        return text;
      }

    private:
      /// The rule: the tissue of each listed material id, tissue 0 (bone)
      /// for the bone segments' ids. The mesh holds no other id
      /// (check_and_add()).
      struct TissueOfMaterialId : TissueRule
      {
        std::map<types::material_id, unsigned char> tissue_of_id;

        unsigned int
        tissue(
          const Triangulation<3>::active_cell_iterator &cell) const override
        {
          const auto listed = tissue_of_id.find(cell->material_id());
          AssertThrow(listed != tissue_of_id.end(),
                      ExcMessage("Material id " +
                                 std::to_string(cell->material_id()) +
                                 " has no tissue in the scene's effects."));
          return listed->second;
        }
      };

      std::map<types::material_id, double> youngs_moduli;
      std::map<types::material_id, double> poissons_ratios;
    };

    SOFTFACE_REGISTER_EFFECT(HeterogeneousTissue,
                             "heterogeneous tissue",
                             "Young's modulus and Poisson's ratio per "
                             "material id (tissue label), in every model.")
  } // namespace Effects
} // namespace softface

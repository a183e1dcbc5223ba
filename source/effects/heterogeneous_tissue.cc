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
          "stiffer than muscle stiffer than fat, fat at the seed's "
          "homogeneous 3000 Pa; published values spread over an order of "
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

      std::string
      apply(Scene &scene) const override
      {
        std::set<types::material_id> bone;
        for (const auto &segment : scene.segments)
          bone.insert(segment.material_ids.begin(), segment.material_ids.end());

        // Tissue 0 is Scene::material (bone cells); one per listed id.
        std::vector<Material>                  tissues = {scene.material};
        std::map<types::material_id, unsigned> index;
        for (const auto &[id, E] : youngs_moduli)
          {
            Material tissue          = scene.material;
            tissue.youngs_modulus_pa = E;
            if (poissons_ratios.count(id))
              tissue.poissons_ratio = poissons_ratios.at(id);
            index[id] = tissues.size();
            tissues.push_back(tissue);
          }

        // The rule per material id (a rank's part applies it to its own
        // cells), then every cell's tissue by it; the scene takes both once
        // every cell has one.
        std::map<types::material_id, unsigned char> rule;
        for (const auto &id : bone)
          rule[id] = 0;
        for (const auto &[id, t] : index)
          rule[id] = t;

        std::vector<unsigned char>             tissue_of_cell;
        std::map<types::material_id, unsigned> n_cells;
        tissue_of_cell.reserve(scene.triangulation.n_active_cells());
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          {
            const auto id = cell->material_id();
            ++n_cells[id];
            if (const auto listed = rule.find(id); listed != rule.end())
              tissue_of_cell.push_back(listed->second);
            else
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
          }
        scene.effects.tissues               = std::move(tissues);
        scene.effects.tissue_of_cell        = std::move(tissue_of_cell);
        scene.effects.tissue_of_material_id = std::move(rule);

        std::ostringstream line;
        line << "heterogeneous tissue:";
        for (const auto &[id, count] : n_cells)
          if (index.count(id))
            line << " id " << int(id) << " E "
                 << scene.effects.tissues[index.at(id)].youngs_modulus_pa
                 << " Pa nu "
                 << scene.effects.tissues[index.at(id)].poissons_ratio << " ("
                 << count << " cells);";
          else
            line << " id " << int(id) << " bone (" << count << " cells);";
        std::string text = line.str();
        text.pop_back();
        return text;
      }

    private:
      std::map<types::material_id, double> youngs_moduli;
      std::map<types::material_id, double> poissons_ratios;
    };

    SOFTFACE_REGISTER_EFFECT(HeterogeneousTissue,
                             "heterogeneous tissue",
                             "Young's modulus and Poisson's ratio per "
                             "material id (tissue label), in every model.")
  } // namespace Effects
} // namespace softface

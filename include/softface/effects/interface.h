#ifndef softface_effects_interface_h
#define softface_effects_interface_h

#include <deal.II/base/parameter_handler.h>

#include <softface/core/plugin_registry.h>
#include <softface/core/scene.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Effects: what a scene may call for beyond homogeneous tissue moved by
   * its bones (heterogeneous tissue, gravity, ...). A scene names them in
   * "Effects/Effects"; each has a subsection of its own and registers itself
   * in one line (SOFTFACE_REGISTER_EFFECT), like a model. An effect adds
   * its contribution to the scene (SceneEffects in core/scene.h): rules per
   * cell (tissues, body forces) that every part of softface applies to its
   * own cells, and constraints on free vertices; a model says which
   * contributions it honours, and a
   * scene that calls an effect a selected model cannot simulate stops before
   * any work (check_supported()). Nothing of an effect is built, stored or
   * evaluated when the scene does not name it.
   */
  namespace Effects
  {
    class Interface
    {
    public:
      virtual ~Interface() = default;

      /// Read the effect's own subsection (the handler is already inside).
      virtual void
      parse_parameters(ParameterHandler &prm);

      /**
       * Change the mesh before its DoFs are distributed (split it along a
       * slit, relabel contact faces); @p scene's triangulation and segments
       * exist, its DoFs are those of the mesh as read. Returns one line for
       * the log, or nothing if the mesh is unchanged (the default).
       */
      virtual std::string
      prepare_mesh(Scene &scene) const;

      /// The SceneEffects::Contribution flags a model must honour.
      virtual unsigned int
      contributions() const = 0;

      /**
       * Declare the effect's rules per cell in @p scene's effects
       * (SceneEffects: tissues and tissue_rule, body_force_rules;
       * core/cell_rules.h), by which every part of softface computes the
       * effect's contribution to its own cells. Called on every MPI rank,
       * whether or not it holds the scene's cells, once the segments are
       * known; reads nothing of the mesh. The default declares none.
       */
      virtual void
      declare_rules(Scene &scene) const;

      /**
       * Add the effect to @p scene, which holds its cells (after
       * Scene::setup(): the mesh, its DoFs and join points exist):
       * declare_rules(), check the mesh and add what needs it whole
       * (check_and_add()), then apply the rules to every cell
       * (Scene::apply_rules()). Returns one line for the log.
       */
      std::string
      apply(Scene &scene) const;

    protected:
      /**
       * What apply() does with the scene's mesh beyond the rules: throw a
       * clear error if the mesh does not fit the parameters (a material id
       * without parameters), add what needs the whole mesh (constraints on
       * free vertices). Returns one line for the log: what the effect added.
       */
      virtual std::string
      check_and_add(Scene &scene) const = 0;
    };

    /// Names of all registered effects, in alphabetical order.
    std::vector<std::string>
    registered_names();

    /// The Effects section: the list of effects and each one's subsection.
    void
    declare_parameters(ParameterHandler &prm);

    /// The names in "Effects/Effects" (none by default); throws a clear
    /// error naming an unknown or repeated one.
    std::vector<std::string>
    selected_names(ParameterHandler &prm);

    /// Create the effect called @p name and let it parse its subsection.
    std::unique_ptr<Interface>
    create(const std::string &name, ParameterHandler &prm);

    /**
     * Throw one clear error naming @p model and @p effect_name unless the
     * model honours (@p honoured: its SceneEffects::Contribution flags)
     * every contribution of @p effect.
     */
    void
    check_supported(const std::string &model,
                    const unsigned int honoured,
                    const std::string &effect_name,
                    const Interface   &effect);

    /**
     * A value per material id, "1: 15000, 3: 6000" -> {1: 15000, 3: 6000},
     * as the effects' parameters give them. Throws an error that starts
     * with @p entry for a malformed pair, an id outside 0..255, a repeated
     * id or a value that is not a finite number.
     */
    std::map<types::material_id, double>
    parse_material_values(const std::string &entry, const std::string &text);

    /**
     * A box 'x0, x1, y0, y1, z0, z1' (mm) that limits where an effect
     * applies; an empty text is everything. Throws an error that starts with
     * @p entry for anything else.
     */
    struct Region
    {
      Point<3> lower, upper;
      bool     everywhere = true;
      bool
      contains(const Point<3> &p) const
      {
        if (everywhere)
          return true;
        for (unsigned int d = 0; d < 3; ++d)
          if (p[d] < lower[d] || p[d] > upper[d])
            return false;
        return true;
      }
    };
    Region
    parse_region(const std::string &entry, const std::string &text);

    /// The entry 'Maximum active-set iterations' of an effect whose
    /// constraints are unilateral.
    void
    declare_active_set_iterations(ParameterHandler &prm);

    /// One line per effect: name and description (for --help).
    std::string
    describe_registered();

    namespace internal
    {
      using Registration = PluginRegistry<Interface>::Registration;

      /// Throws if @p name is registered already.
      bool
      register_effect(const std::string &name, Registration registration);
    } // namespace internal
  }   // namespace Effects
} // namespace softface

/**
 * Register an effect class under the name a parameter file uses. The class
 * needs a default constructor and a static declare_parameters(prm) that
 * declares the entries of its own subsection (the handler is inside it).
 */
#define SOFTFACE_REGISTER_EFFECT(classname, name, description)   \
  namespace                                                      \
  {                                                              \
    const bool softface_registered_effect_##classname =          \
      softface::Effects::internal::register_effect(              \
        name,                                                    \
        {description,                                            \
         &classname::declare_parameters,                         \
         []() -> std::unique_ptr<softface::Effects::Interface> { \
           return std::make_unique<classname>();                 \
         }});                                                    \
  }

#endif

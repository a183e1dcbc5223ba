#ifndef softface_models_interface_h
#define softface_models_interface_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>

#include <functional>
#include <ostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Models
  {
    /// What a model reports about its last setup() and solve().
    struct Statistics
    {
      double       setup_time = 0.; ///< s, wall clock
      double       solve_time = 0.; ///< s, wall clock
      unsigned int iterations = 0;
      double       residual   = 0.; ///< the model's own measure at the end
      /// Finer phases (name, s), printed under the summary table.
      std::vector<std::pair<std::string, double>> phases;
      /// Model-specific figures (name, value), printed with the phases.
      std::vector<std::pair<std::string, std::string>> details;
    };

    /**
     * What every soft-tissue model offers. A model works on the scene's one
     * DoF layout: setup() once per scene (everything that does not depend on
     * the planning), then solve() for any number of plannings.
     */
    class Interface
    {
    public:
      virtual ~Interface() = default;

      /// Read the model's own subsection (the handler is already inside it).
      virtual void
      parse_parameters(ParameterHandler &prm);

      virtual void
      setup(const Scene &scene) = 0;

      /**
       * Compute the displacement of every vertex. @p prescribed holds the
       * join points' displacement (its free entries are ignored); on return
       * @p displacement equals it on the join DoFs.
       */
      virtual void
      solve(const Vector<double> &prescribed, Vector<double> &displacement) = 0;

      const Statistics &
      statistics() const;

      /**
       * The displacement field between the vertices, for evaluation at
       * arbitrary points: a model on its own layout (the quadratic
       * reference) returns it here; by default nothing, and the vertex
       * values solve() returned are interpolated linearly.
       */
      virtual std::pair<const DoFHandler<3> *, const Vector<double> *>
      displacement_field() const;

      /**
       * Where a long solve reports its progress (load steps, sweeps); none
       * by default. The simulator points it at stdout.
       */
      void
      set_progress_stream(std::ostream *stream);

    protected:
      Statistics    stats;
      std::ostream *progress = nullptr;
    };

    /// Names of all registered models, in alphabetical order.
    std::vector<std::string>
    registered_names();

    /// The Models section: the list of models and each model's subsection.
    void
    declare_parameters(ParameterHandler &prm);

    /// The names in "Models/Models" of a parsed handler.
    std::vector<std::string>
    selected_names(ParameterHandler &prm);

    /// Create the model called @p name and let it parse its subsection.
    std::unique_ptr<Interface>
    create(const std::string &name, ParameterHandler &prm);

    /// One line per model: name and description (for --help).
    std::string
    describe_registered();

    namespace internal
    {
      struct Registration
      {
        std::string                                 description;
        std::function<void(ParameterHandler &)>     declare_parameters;
        std::function<std::unique_ptr<Interface>()> factory;
      };

      bool
      register_model(const std::string &name, Registration registration);
    } // namespace internal
  }   // namespace Models
} // namespace softface

/**
 * Register a model class under the name a parameter file uses. The class
 * needs a default constructor and a static declare_parameters(prm) that
 * declares the entries of its own subsection (the handler is inside it).
 */
#define SOFTFACE_REGISTER_MODEL(classname, name, description)   \
  namespace                                                     \
  {                                                             \
    const bool softface_registered_##classname =                \
      softface::Models::internal::register_model(               \
        name,                                                   \
        {description,                                           \
         &classname::declare_parameters,                        \
         []() -> std::unique_ptr<softface::Models::Interface> { \
           return std::make_unique<classname>();                \
         }});                                                   \
  }

#endif

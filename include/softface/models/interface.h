#ifndef softface_models_interface_h
#define softface_models_interface_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/vector.h>

#include <softface/core/plugin_registry.h>
#include <softface/core/scene.h>

#include <functional>
#include <limits>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  class DistributedLayout;
  class SharedDistributedLayout;
  class BlockColouring;
  class PointExchange;
  struct PointMesh;

  namespace Models
  {
    /**
     * One of a model's own figures (sweeps, precision, Newton iterations per
     * load step, ...), printed under the summary table and written to
     * summary.csv. A figure that depends on timing (ns per update) is marked
     * so that outputs meant to be reproducible can leave it out.
     */
    struct Detail
    {
      std::string name;
      /// The value of a numeric figure (NaN for a text figure).
      double value = std::numeric_limits<double>::quiet_NaN();
      /// The value of a text figure (empty for a numeric one).
      std::string text;
      std::string unit;
      bool        depends_on_timing = false;

      /// As printed: numbers with @p digits significant digits (integers
      /// whole) or, with digits == 0, in full (round-trip) precision.
      std::string
      formatted(const unsigned int digits = 3) const;
    };

    /// What a model reports about its last setup() and solve().
    struct Statistics
    {
      /// s, wall clock of setup() and solve(), diagnostic phases excluded
      double       setup_time = 0.;
      double       solve_time = 0.;
      unsigned int iterations = 0;
      double       residual   = 0.; ///< the model's own relative measure
      /// The unknowns the model solves for, join DoFs included (0: the
      /// shared layout's, three per vertex).
      unsigned int n_dofs = 0;
      /// Durations (s) of the phases of setup() and then of solve(), in the
      /// order they first ran; a phase entered several times (Newton
      /// assembly) shows its total. Diagnostic phases (not counted in the
      /// setup and solve times) are marked "(diagnostic)".
      std::vector<std::pair<std::string, double>> phases;
      std::vector<Detail>                         details;
      /// Results that hold but that a user must know about (e.g. inverted
      /// tetrahedra); the simulator prints them.
      std::vector<std::string> warnings;
    };

    /// The prescribed displacement (like solve()'s) at a load in (0, 1].
    using LoadPath = std::function<Vector<double>(const double load)>;

    /**
     * What a model reads of the run it is part of, handed to setup() and
     * kept for every later solve().
     */
    struct RunContext
    {
      /// Where a long solve reports its progress (load steps, sweeps);
      /// nullptr: silent. The simulator points it at stdout.
      std::ostream *progress = nullptr;
      /**
       * The MPI ranks that share the model's work. On more than one, the
       * distributed models (linear FEM, the mass tensor and mass spring
       * models) spread it over them at setup(); MPI_COMM_SELF keeps a model
       * whole on this rank in an MPI run.
       */
      MPI_Comm communicator = MPI_COMM_WORLD;
      /// The run's layout on its ranks, shared by its distributed models;
      /// none: a distributed model partitions the scene itself, in cell
      /// order.
      std::shared_ptr<SharedDistributedLayout> layout;
    };

    /**
     * What a model reads of the plan it solves besides the prescribed
     * displacement, handed to solve() and referenced until it returns.
     */
    struct PlanContext
    {
      /**
       * How the planning is reached by a model that applies it in load
       * steps (the nonlinear ones): the simulator hands the rigid path,
       * each moved bone turned and translated the load's fraction of its
       * motion (Planning::prescribed_displacement()). Empty: the final
       * displacement scaled by the load.
       */
      LoadPath load_path;
      /**
       * A guess of the answer (a linear model's answer to the same plan),
       * or nullptr. The nonlinear models start their first load step from
       * it when it goes to the full load (the quadratic reference at degree
       * 1 only: at degree 2 it has DoFs between the vertices); the others
       * ignore it.
       */
      const Vector<double> *initial_guess = nullptr;
      /**
       * The answer of the model converged_equivalent() names to this plan,
       * or nullptr: the model solves those equations itself if it needs
       * them.
       */
      const Vector<double> *converged_answer = nullptr;
      /// No progress reports (the solves of a response basis).
      bool silent = false;
    };

    /**
     * What every soft-tissue model offers. A model works on the scene's one
     * DoF layout: setup() once per scene (everything that does not depend on
     * the planning), then solve() for any number of plannings. Both are
     * timed here, the same way for every model; a model implements
     * do_setup() and do_solve() and names its phases with phase().
     */
    class Interface
    {
    public:
      Interface();
      virtual ~Interface() = default;

      /// Read the model's own subsection (the handler is already inside it).
      virtual void
      parse_parameters(ParameterHandler &prm);

      /**
       * The SceneEffects::Contribution flags (core/scene.h) the model
       * honours: a scene whose effects need others stops before any work
       * (effects/interface.h). None by default.
       */
      virtual unsigned int
      honoured_effects() const;

      /**
       * True if the model's answer on @p scene is affine in the prescribed
       * displacement (the answer to a sum of two is the sum of the answers,
       * less the answer to none), so that a ResponseBasis can stand in for
       * its solves. False by default.
       */
      virtual bool
      linear_in_motion(const Scene &scene) const;

      /// Everything that does not depend on the planning, in the run
      /// @p context describes.
      void
      setup(const Scene &scene, const RunContext &context = RunContext());

      /**
       * Compute the displacement of every vertex. @p prescribed holds the
       * join points' displacement (its free entries are ignored); on return
       * @p displacement equals it on the join DoFs. @p plan: what else the
       * model may read of this plan.
       */
      void
      solve(const Vector<double> &prescribed,
            Vector<double>       &displacement,
            const PlanContext    &plan = PlanContext());

      const Statistics &
      statistics() const;

      /**
       * The displacement field between the vertices, for evaluation at
       * arbitrary points: a model on its own layout (the quadratic
       * reference) returns it here; by default nothing, and the vertex
       * values solve() returned are interpolated linearly. Nothing either
       * where the field lives on the MPI ranks' parts of the mesh: there
       * displacement_field_at() gives it.
       */
      virtual std::pair<const DoFHandler<3> *, const Vector<double> *>
      displacement_field() const;

      /**
       * On several MPI ranks, where a model's field lives on the ranks'
       * parts of the mesh: the field at @p points, which lie in the scene's
       * active cells @p cells at @p reference_points there, into @p values
       * on every rank; false (on every rank) if the model has no such field.
       * Collective; throws on every rank if a point's reference coordinates
       * do not map to it in the ranks' cell of that number.
       */
      virtual bool
      displacement_field_at(const std::vector<Point<3>>     &points,
                            const std::vector<unsigned int> &cells,
                            const std::vector<Point<3>>     &reference_points,
                            std::vector<Tensor<1, 3>>       &values) const;

      /**
       * The registered model whose answer is this one's converged answer
       * (the same equations solved exactly), or empty. The mass tensor
       * model: "linear fem". With PlanContext::converged_answer a model can
       * then measure its precision without solving them again.
       */
      virtual std::string
      converged_equivalent() const;

      /**
       * Whether the model, on several MPI ranks, reads nothing of the
       * scene's cells (its triangulation, serial DoFHandler and arrays per
       * cell), so that the members of a group of ranks (Models/Mesh group
       * size) need not hold them (Scene::has_cells()). Default: false.
       */
      virtual bool
      runs_without_scene_cells() const;

    protected:
      /**
       * The scene's layout on the model's ranks (more than one): the shared
       * one, or else one of the model's own. Collective when it is built.
       */
      const DistributedLayout &
      distributed_layout(const Scene &scene);

      /// RunContext::communicator.
      MPI_Comm communicator = MPI_COMM_WORLD;

      virtual void
      do_setup(const Scene &scene) = 0;
      virtual void
      do_solve(const Vector<double> &prescribed,
               Vector<double>       &displacement) = 0;

      /**
       * Time a phase of setup or solve until the returned scope ends. A
       * @p diagnostic phase (e.g. the converged answer a precision is
       * measured against) is reported but not counted in the setup or solve
       * time: it is not the model's work.
       */
      TimerOutput::Scope
      phase(const std::string &name, const bool diagnostic = false);
      /// The timer behind phase(), for components that enter phases.
      TimerOutput &
      timer();

      void
      set_iterations(const unsigned int iterations);
      void
      set_residual(const double relative_residual);
      /// For a model on a layout of its own (see Statistics::n_dofs).
      void
      set_n_dofs(const unsigned int n_dofs);
      /// A numeric figure; @p depends_on_timing for time-derived ones.
      void
      add_detail(const std::string &name,
                 const double       value,
                 const std::string &unit              = "",
                 const bool         depends_on_timing = false);
      /// A text figure.
      void
      add_detail(const std::string &name, const std::string &text);
      /**
       * A point model's ranges of blocks on the ranks of its communicator,
       * timed as its "partition" phase, with its "MPI ranks"
       * figure; none on one rank, or where the scene has vertex constraints
       * (a constrained step moves its partner, which another rank may own:
       * every rank then runs the model whole). Collective.
       */
      std::unique_ptr<PointExchange>
      point_exchange(const Scene          &scene,
                     const BlockColouring &colouring,
                     const PointMesh      &mesh);
      void
      warn(const std::string &message);

      /// From the contexts: RunContext::progress (nullptr in a silent
      /// solve) and, during solve(), the PlanContext's entries.
      std::ostream         *progress = nullptr;
      LoadPath              load_path;
      const Vector<double> *initial_guess    = nullptr;
      const Vector<double> *converged_answer = nullptr;

    private:
      std::ostream                            *run_progress = nullptr;
      std::shared_ptr<SharedDistributedLayout> shared_layout, own_layout;
      /// The phases the timer holds, in the order they first ran, and
      /// the time the diagnostic ones took.
      std::vector<std::pair<std::string, double>>
      collect_phases(double &diagnostic_time);

      TimerOutput              timer_output;
      std::vector<std::string> phase_order;
      std::vector<std::string> diagnostic_phases;
      // setup()'s part of the statistics stays for every later solve().
      std::vector<std::pair<std::string, double>> setup_phases;
      std::vector<Detail>                         setup_details;
      std::vector<std::string>                    setup_warnings;
      Statistics                                  stats;
    };

    /// True if a vertex of @p scene may lift off a surface (unilateral
    /// contact): no model's answer is then linear in the motion.
    bool
    has_unilateral_contact(const Scene &scene);

    /// Names of all registered models, in alphabetical order.
    std::vector<std::string>
    registered_names();

    /// The Models section: the list of models and each model's subsection.
    void
    declare_parameters(ParameterHandler &prm);

    /// The names in "Models/Models" of a parsed handler; throws a clear
    /// error naming an unknown one.
    std::vector<std::string>
    selected_names(ParameterHandler &prm);

    /// "Models/Threads" of a parsed handler (0: every core).
    unsigned int
    selected_threads(ParameterHandler &prm);
    /// Create the model called @p name and let it parse its subsection.
    std::unique_ptr<Interface>
    create(const std::string &name, ParameterHandler &prm);

    /// One line per model: name and description (for --help).
    std::string
    describe_registered();

    namespace internal
    {
      using Registration = PluginRegistry<Interface>::Registration;

      /// Throws if @p name is registered already.
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

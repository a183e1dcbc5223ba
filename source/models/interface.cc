// The model plugin layer (models): the interface every model implements, how
// setup() and solve() are timed and reported the same way for all, and the
// registry that the one-line SOFTFACE_REGISTER_MODEL fills.

#include <deal.II/base/utilities.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>
#include <softface/models/interface.h>
#include <softface/models/point_exchange.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

namespace softface
{
  namespace Models
  {
    namespace
    {
      // Function-local so that registrations from static initialisers in
      // any translation unit find it constructed.
      PluginRegistry<Interface> &
      registry()
      {
        static PluginRegistry<Interface> models("model", "a", "Models");
        return models;
      }
    } // namespace

    std::string
    Detail::formatted(const unsigned int digits) const
    {
      if (!std::isfinite(value))
        return text;
      std::string number;
      if (value == std::round(value) && std::abs(value) < 1e15)
        number = std::to_string(static_cast<long long>(value));
      else if (digits == 0)
        {
          char       buffer[32];
          const auto end = std::to_chars(buffer, buffer + 32, value).ptr;
          number         = std::string(buffer, end);
        }
      else
        {
          std::ostringstream s;
          s << std::setprecision(digits) << value;
          number = s.str();
        }
      return unit.empty() ? number : number + ' ' + unit;
    }

    Interface::Interface()
        : timer_output(std::cout, TimerOutput::never, TimerOutput::wall_times)
    {}

    void
    Interface::parse_parameters(ParameterHandler &)
    {}

    unsigned int
    Interface::honoured_effects() const
    {
      return SceneEffects::none;
    }

    bool
    Interface::linear_in_motion(const Scene &) const
    {
      return false;
    }

    bool
    has_unilateral_contact(const Scene &scene)
    {
      for (const auto &constraint : scene.effects.vertex_constraints)
        if (constraint.unilateral)
          return true;
      return false;
    }

    bool
    Interface::runs_without_scene_cells() const
    {
      return false;
    }

    void
    Interface::setup(const Scene &scene, const RunContext &context)
    {
      run_progress  = context.progress;
      progress      = context.progress;
      communicator  = context.communicator;
      shared_layout = context.layout;
      stats         = Statistics();
      setup_phases.clear();
      setup_details.clear();
      setup_warnings.clear();
      timer_output.reset();
      phase_order.clear();
      diagnostic_phases.clear();
      Timer wall;
      do_setup(scene);
      double diagnostic_time = 0.;
      setup_phases           = collect_phases(diagnostic_time);
      stats.setup_time       = wall.wall_time() - diagnostic_time;
      setup_details          = stats.details;
      setup_warnings         = stats.warnings;
      stats.phases           = setup_phases;
    }

    void
    Interface::solve(const Vector<double> &prescribed,
                     Vector<double>       &displacement,
                     const PlanContext    &plan)
    {
      progress         = plan.silent ? nullptr : run_progress;
      load_path        = plan.load_path;
      initial_guess    = plan.initial_guess;
      converged_answer = plan.converged_answer;
      // Referenced only while this solve runs, also when it throws.
      struct Forget
      {
        Interface *model;
        ~Forget()
        {
          model->initial_guess    = nullptr;
          model->converged_answer = nullptr;
          model->load_path        = LoadPath();
          model->progress         = model->run_progress;
        }
      } forget{this};
      const double       setup_time = stats.setup_time;
      const unsigned int n_dofs     = stats.n_dofs;
      stats                         = Statistics();
      stats.setup_time              = setup_time;
      stats.n_dofs                  = n_dofs;
      stats.details                 = setup_details;
      stats.warnings                = setup_warnings;
      timer_output.reset();
      phase_order.clear();
      diagnostic_phases.clear();
      Timer wall;
      do_solve(prescribed, displacement);
      double     diagnostic_time = 0.;
      const auto solve_phases    = collect_phases(diagnostic_time);
      stats.solve_time           = wall.wall_time() - diagnostic_time;
      stats.phases               = setup_phases;
      stats.phases.insert(stats.phases.end(),
                          solve_phases.begin(),
                          solve_phases.end());
    }

    std::vector<std::pair<std::string, double>>
    Interface::collect_phases(double &diagnostic_time)
    {
      const auto seconds =
        timer_output.get_summary_data(TimerOutput::total_wall_time);
      std::vector<std::string> names = phase_order;
      for (const auto &entry : seconds)
        if (std::find(names.begin(), names.end(), entry.first) == names.end())
          names.push_back(entry.first);
      std::vector<std::pair<std::string, double>> phases;
      diagnostic_time = 0.;
      for (const auto &name : names)
        if (seconds.count(name))
          {
            const bool diagnostic = std::find(diagnostic_phases.begin(),
                                              diagnostic_phases.end(),
                                              name) != diagnostic_phases.end();
            if (diagnostic)
              diagnostic_time += seconds.at(name);
            phases.emplace_back(diagnostic ? name + " (diagnostic)" : name,
                                seconds.at(name));
          }
      timer_output.reset();
      phase_order.clear();
      diagnostic_phases.clear();
      return phases;
    }

    const Statistics &
    Interface::statistics() const
    {
      return stats;
    }

    std::pair<const DoFHandler<3> *, const Vector<double> *>
    Interface::displacement_field() const
    {
      return {nullptr, nullptr};
    }

    bool
    Interface::displacement_field_at(const std::vector<Point<3>> &,
                                     const std::vector<unsigned int> &,
                                     const std::vector<Point<3>> &,
                                     std::vector<Tensor<1, 3>> &) const
    {
      return false;
    }

    std::string
    Interface::converged_equivalent() const
    {
      return "";
    }

    const DistributedLayout &
    Interface::distributed_layout(const Scene &scene)
    {
      if (shared_layout && shared_layout->communicator == communicator)
        return shared_layout->get(scene);
      // The model's own, made anew for each setup (a scene at the address
      // of an earlier one is not that scene).
      own_layout = std::make_shared<SharedDistributedLayout>(
        communicator, DistributedLayout::Partitioner::cell_order);
      return own_layout->get(scene);
    }

    TimerOutput::Scope
    Interface::phase(const std::string &name, const bool diagnostic)
    {
      if (std::find(phase_order.begin(), phase_order.end(), name) ==
          phase_order.end())
        phase_order.push_back(name);
      if (diagnostic)
        diagnostic_phases.push_back(name);
      return TimerOutput::Scope(timer_output, name);
    }

    std::unique_ptr<PointExchange>
    Interface::point_exchange(const Scene          &scene,
                              const BlockColouring &colouring,
                              const PointMesh      &mesh)
    {
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(communicator);
      if (n_ranks == 1)
        return nullptr;
      if (scene.has_vertex_constraints())
        {
          add_detail("MPI ranks",
                     "1 (vertex constraints: whole on every rank)");
          return nullptr;
        }
      const auto partition = phase("partition");
      auto       exchange =
        std::make_unique<PointExchange>(colouring, mesh, communicator);
      add_detail("MPI ranks", n_ranks);
      return exchange;
    }

    TimerOutput &
    Interface::timer()
    {
      return timer_output;
    }

    void
    Interface::set_iterations(const unsigned int iterations)
    {
      stats.iterations = iterations;
    }

    void
    Interface::set_residual(const double relative_residual)
    {
      stats.residual = relative_residual;
    }

    void
    Interface::set_n_dofs(const unsigned int n_dofs)
    {
      stats.n_dofs = n_dofs;
    }

    void
    Interface::add_detail(const std::string &name,
                          const double       value,
                          const std::string &unit,
                          const bool         depends_on_timing)
    {
      Detail d;
      d.name              = name;
      d.value             = value;
      d.unit              = unit;
      d.depends_on_timing = depends_on_timing;
      stats.details.push_back(d);
    }

    void
    Interface::add_detail(const std::string &name, const std::string &text)
    {
      Detail d;
      d.name = name;
      d.text = text;
      stats.details.push_back(d);
    }

    void
    Interface::warn(const std::string &message)
    {
      stats.warnings.push_back(message);
    }

    bool
    internal::register_model(const std::string &name, Registration registration)
    {
      return registry().add(name, std::move(registration));
    }

    std::vector<std::string>
    registered_names()
    {
      return registry().names();
    }

    void
    declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Models");
      prm.declare_entry("Models",
                        "linear fem",
                        Patterns::List(Patterns::Anything(), 1),
                        "The soft-tissue models to run on the scene, side by "
                        "side on the same mesh and join points. Available: " +
                          registry().joined_names() + ".");
      prm.declare_entry(
        "Threads",
        "0",
        Patterns::Integer(0),
        "Threads for the P1 assembly of linear and nonlinear FEM, the mass "
        "tensor and mass spring sweeps (scenes with sliding contact or "
        "separated lips sweep on one) and deal.II's vector and matrix "
        "operations; 0 means "
        "every core, and more than the cores count as the cores "
        "(the environment variable DEAL_II_NUM_THREADS caps it). "
        "Assembly and sweeps give the same numbers on any number of threads; "
        "deal.II's vector operations sum long vectors in pieces per thread, "
        "which moves an iterative solver's answer by round-off (about 1e-12 "
        "relative at 491k tetrahedra, far below its tolerance). The linear "
        "solvers' preconditioners (Trilinos ML, CHOLMOD), the mesh read and "
        "the quadratic reference's assembly run on one.");
      DistributedLayout::declare_partitioner(prm);
      registry().declare_subsections(prm);
      prm.leave_subsection();
    }

    unsigned int
    selected_threads(ParameterHandler &prm)
    {
      prm.enter_subsection("Models");
      const unsigned int n = prm.get_integer("Threads");
      prm.leave_subsection();
      return n;
    }

    std::vector<std::string>
    selected_names(ParameterHandler &prm)
    {
      const auto names = registry().selected(prm);
      // An empty list would run nothing and succeed.
      if (names.empty())
        throw Error("Models/Models: no model is named (available: " +
                    registry().joined_names() + ").");
      return names;
    }

    std::unique_ptr<Interface>
    create(const std::string &name, ParameterHandler &prm)
    {
      return registry().create(name, prm);
    }

    std::string
    describe_registered()
    {
      return registry().describe();
    }
  } // namespace Models
} // namespace softface

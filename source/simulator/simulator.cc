// Runs a scene (simulator): reads the parameter file in two passes, builds the
// scene and the planning, runs the selected models side by side (a failing
// model is reported and the others go on), and writes the report and fields.

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <softface/core/process.h>
#include <softface/core/scene.h>
#include <softface/core/threads.h>
#include <softface/models/interface.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/report.h>
#include <softface/outputs/skin_output.h>
#include <softface/simulator/model_runner.h>
#include <softface/simulator/parameters.h>
#include <softface/simulator/prepared.h>
#include <softface/simulator/rank_policy.h>
#include <softface/simulator/simulator.h>

#include <iomanip>
#include <ostream>
#include <string>

namespace softface
{

  Simulator::Simulator()  = default;
  Simulator::~Simulator() = default;

  int
  Simulator::run(const std::string &filename,
                 std::ostream      &out_of_rank_0,
                 std::ostream      &err_of_rank_0)
  {
    // On several MPI ranks, rank 0 speaks for all: they take the same
    // decisions on the same scene.
    RankPolicy::SilentBuffer discard;
    std::ostream             silent(&discard);
    const bool speaks = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    std::ostream &out = speaks ? out_of_rank_0 : silent;
    std::ostream &err = speaks ? err_of_rank_0 : silent;
    prepare(filename, out);

    // A model that fails (no convergence, a motion it cannot follow) is
    // reported and left out; the others still run, and the exit code says
    // that something failed.
    model_runs.clear();
    ModelRunner        runner(*the_scene,
                       state->plannings,
                       state->layout,
                       out,
                       err,
                       [&](const Report::ModelRun &run,
                           Models::Interface      &model,
                           const bool              from_basis) {
                         hand_to_outputs(run, model, from_basis);
                       });
    const unsigned int n_failed = runner.run_all(state->models, model_runs);

    Report::compare_to(*the_scene, reference, model_runs);
    out << '\n';
    Report::print(*the_scene, model_runs, reference, true, out);
    write_outputs(out);
    print_closing(out);
    if (n_failed > 0)
      {
        std::string names;
        for (const auto &run : model_runs)
          if (run.failed)
            names += (names.empty() ? "" : ", ") + run.label();
        err << "softface: " << n_failed
            << (state->plannings.plans.size() > 1 ? " run(s) failed: " :
                                                    " model(s) failed: ")
            << names << std::endl;
        return 1;
      }
    return 0;
  }

  void
  Simulator::hand_to_outputs(const Report::ModelRun &run,
                             Models::Interface      &model,
                             const bool              from_basis)
  {
    for (const auto &output : state->outputs)
      output->add_answer(*state->run, run, model, from_basis);
  }

  void
  Simulator::write_outputs(std::ostream &out)
  {
    for (const auto &output : state->outputs)
      output->write(*state->run, out);
  }

  void
  Simulator::print_closing(std::ostream &out) const
  {
    const auto        &output = state->output;
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    Utilities::System::MemoryStats memory;
    Utilities::System::get_memory_stats(memory);
    const double peak_mb =
      Utilities::MPI::max(memory.VmHWM / 1024., MPI_COMM_WORLD);
    // The ranks differ where a group's members hold no scene cells.
    const double smallest_peak_mb =
      Utilities::MPI::min(memory.VmHWM / 1024., MPI_COMM_WORLD);
    std::string files;
    for (const auto &output : state->outputs)
      if (const std::string written = output->files(*state->run);
          !written.empty())
        files += written + ", ";
    out << "\nOutputs in " << output.directory << "/ (" << files
        << "input.prm, parameters.prm)\n"
        << "Wall time " << std::setprecision(2) << Process::wall_time()
        << " s (the whole process, "
        << (n_ranks > 1 ? std::to_string(n_ranks) + " MPI ranks x " :
                          std::string())
        << Threads::n_threads()
        << (Threads::n_threads() == 1 ? " thread" : " threads")
        << "), peak memory " << std::fixed << std::setprecision(0) << peak_mb
        << " MB";
    if (n_ranks > 1)
      out << " (the largest rank; the smallest " << smallest_peak_mb << " MB)";
    out << std::endl;
  }

  const Scene &
  Simulator::scene() const
  {
    Assert(the_scene, ExcMessage("Simulator::run() first."));
    return *the_scene;
  }

  ParameterHandler &
  Simulator::parameters()
  {
    Assert(state, ExcMessage("Simulator::prepare() first."));
    return state->prm;
  }

  const PlanningList &
  Simulator::plannings() const
  {
    Assert(state, ExcMessage("Simulator::prepare() first."));
    return state->plannings;
  }

  std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>> &
  Simulator::models()
  {
    Assert(state, ExcMessage("Simulator::prepare() first."));
    return state->models;
  }

  SkinOutput *
  Simulator::skin() const
  {
    Assert(state, ExcMessage("Simulator::prepare() first."));
    return state->skin.get();
  }

  const std::vector<Report::ModelRun> &
  Simulator::runs() const
  {
    return model_runs;
  }

  const std::string &
  Simulator::reference_model() const
  {
    return reference;
  }
} // namespace softface

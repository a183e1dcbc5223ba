// Runs a scene (simulator): reads the parameter file in two passes, builds the
// scene and the planning, runs the selected models side by side (a failing
// model is reported and the others go on), and writes the report and fields.

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <softface/core/build_id.h>
#include <softface/core/displacement.h>
#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>
#include <softface/core/on_rank_0.h>
#include <softface/core/parameter_sections.h>
#include <softface/core/planning.h>
#include <softface/core/planning_list.h>
#include <softface/core/process.h>
#include <softface/core/scene.h>
#include <softface/core/sub_communicator.h>
#include <softface/core/threads.h>
#include <softface/core/vec3_parameter.h>
#include <softface/effects/interface.h>
#include <softface/fe/point_evaluation.h>
#include <softface/io/output_file.h>
#include <softface/io/points_csv.h>
#include <softface/models/interface.h>
#include <softface/models/response_basis.h>
#include <softface/patient/backend.h>
#include <softface/simulator/input_files.h>
#include <softface/simulator/model_runner.h>
#include <softface/simulator/output.h>
#include <softface/simulator/parameters.h>
#include <softface/simulator/prepared.h>
#include <softface/simulator/rank_policy.h>
#include <softface/simulator/report.h>
#include <softface/simulator/simulator.h>
#include <softface/simulator/skin_output.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <streambuf>

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
    const Scene &scene = *the_scene;
    // Rank 0 maps for all; its error is every rank's. Every rank knows
    // whether the run maps skins.
    if (!state->skin_parameters.skin_surface.empty())
      on_rank_0(MPI_COMM_WORLD, [&]() {
        state->skin->add_model(run.label(), scene, run.displacement);
      });
    if (state->output.evaluation_points.empty())
      return;
    // A field on the ranks' parts of the mesh (the quadratic reference
    // there) is evaluated by all ranks.
    std::vector<Tensor<1, 3>> values;
    const bool                on_ranks =
      !from_basis && Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1 &&
      model.displacement_field_at(state->evaluation_points,
                                  state->evaluation_cells,
                                  state->evaluation_reference_points,
                                  values);
    const auto [field_dofs, field] = model.displacement_field();
    const auto &evaluation         = state->evaluation;
    if (evaluation && state->writes_outputs)
      write_point_values_csv(evaluation->points(),
                             on_ranks ?
                               values :
                             field_dofs != nullptr && !from_basis ?
                               evaluation->evaluate(*field_dofs, *field) :
                               evaluation->evaluate(scene.dof_handler,
                                                    run.displacement),
                             state->output.directory + "/evaluation_" +
                               Output::file_name_of(run.label()) + ".csv");
  }

  void
  Simulator::write_outputs(std::ostream &out)
  {
    const Scene       &scene  = *the_scene;
    const auto        &output = state->output;
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    if (state->writes_outputs)
      {
        if (state->skin)
          {
            std::vector<std::string> labels;
            for (const auto &run : model_runs)
              labels.push_back(run.label());
            state->skin->order_rows(labels);
            state->skin->write(out);
          }
        Report::write_summary_csv(scene,
                                  model_runs,
                                  reference,
                                  output.directory + "/summary.csv");
        Report::write_statistics(scene,
                                 model_runs,
                                 output.directory + "/statistics");
        if (output.write_vtu && n_ranks == 1)
          Output::write_vtu(scene,
                            model_runs,
                            output.directory + "/solution.vtu");
        if (output.write_nodal_displacements)
          for (const auto &run : model_runs)
            if (!run.failed)
              Output::write_nodal_displacements(
                scene,
                run.displacement,
                output.directory + "/displacements_" +
                  Output::file_name_of(run.label()) + ".csv");
      }

    // On several ranks each writes its piece of the fields, in rank 0's
    // folder (the only one made).
    if (output.write_vtu && n_ranks > 1)
      {
        const std::string stem =
          Utilities::MPI::broadcast(MPI_COMM_WORLD, output.directory, 0) +
          "/solution";
        // From the ranks' parts where a model made them (or a rank holds no
        // cells); a partition for output alone would cost seconds.
        if (state->layout->built() || state->members_without_cells)
          Output::write_pvtu(state->layout->get(scene), model_runs, stem);
        else
          Output::write_pvtu(scene, model_runs, stem, MPI_COMM_WORLD);
      }
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
    out << "\nOutputs in " << output.directory << "/ (summary.csv, statistics"
        << (!output.write_vtu ? "" :
            n_ranks > 1       ? ", solution.pvtu with a piece per rank" :
                                ", solution.vtu")
        << (output.write_nodal_displacements ? ", displacements_*.csv" : "")
        << (state->evaluation ? ", evaluation_*.csv" : "")
        << (state->skin ? ", skin.csv, skin_*.ply/.vtp" : "")
        << ", input.prm, parameters.prm)\n"
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

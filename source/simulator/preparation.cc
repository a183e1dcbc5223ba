// A scene file made ready to run (simulator): the plugins it selects, the
// scene with its effects and plans, the skin and its truth, the outputs it
// asks for, the inputs copied beside them, and the checks that stop a run
// before any model starts.

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <softface/core/build_id.h>
#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>
#include <softface/core/on_rank_0.h>
#include <softface/core/planning.h>
#include <softface/core/planning_list.h>
#include <softface/core/scene.h>
#include <softface/core/sub_communicator.h>
#include <softface/core/threads.h>
#include <softface/effects/interface.h>
#include <softface/io/output_file.h>
#include <softface/models/interface.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/skin_output.h>
#include <softface/patient/pipeline.h>
#include <softface/simulator/input_files.h>
#include <softface/simulator/prepared.h>
#include <softface/simulator/simulator.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace
  {
    // The skin a truth scene predicts (its one model, one mapping), made by
    // running it unless its output folder holds the skin made from the same
    // file (it keeps a copy of its input as input.prm).
    std::string
    post_operative_skin_of(const std::string &truth_scene, std::ostream &out)
    {
      const std::string where =
        "Skin/Post-operative skin '" + truth_scene + "'";
      if (!std::filesystem::exists(truth_scene))
        throw Error(where + ": no such scene file.");
      ParameterHandler prm;
      Simulator::read_parameters(truth_scene, prm);
      OutputParameters output;
      output.parse_parameters(prm);
      const auto models = Models::selected_names(prm);
      prm.enter_subsection("Skin");
      const std::string mapping = prm.get("Mapping");
      prm.leave_subsection();
      if (models.size() != 1 || mapping.find(',') != std::string::npos)
        throw Error(where + ": a truth scene runs one model and one mapping.");
      const std::string skin =
        output.directory + "/skin_" + Outputs::file_name_of(models[0]) + ".ply";
      const auto contents = [](const std::string &file) {
        std::ifstream      in(file);
        std::ostringstream s;
        s << in.rdbuf();
        return in ? s.str() : std::string();
      };
      // The skin is reused only if the same file made it with the same
      // build of softface: a changed model makes another truth.
      const std::string stamp = output.directory + "/truth_build_id.txt";
      const std::string build = library_build_id_of(
        reinterpret_cast<const void *>(&post_operative_skin_of));
      const bool same_scene =
        std::filesystem::exists(skin) &&
        contents(output.directory + "/input.prm") == contents(truth_scene);
      if (same_scene && !build.empty() && contents(stamp) == build)
        {
          out << "  post-operative skin " << skin << " (made by " << truth_scene
              << ")" << std::endl;
          return skin;
        }
      // An older skin must not pass for this scene's if its run fails.
      std::filesystem::remove(skin);
      std::filesystem::remove(stamp);
      out << "  post-operative skin: running the truth scene " << truth_scene
          << (same_scene ? " (its skin was made by another build of softface)" :
                           "")
          << std::endl;
      Simulator truth;
      const int code = truth.run(truth_scene, out, out);
      if (code != 0 || !std::filesystem::exists(skin))
        throw Error(where + ": the truth scene failed (its output is in " +
                    output.directory + ").");
      std::ofstream(stamp) << build;
      out << "  post-operative skin " << skin << " (made by " << truth_scene
          << ")" << std::endl;
      return skin;
    }

  } // namespace

  void
  Simulator::prepare(const std::string &filename, std::ostream &out)
  {
    Timer wall;
    state = std::make_unique<Prepared>();
    create_plugins(filename);
    std::string needs_cells;
    try
      {
        needs_cells = build_scene(filename, out);
      }
    catch (const Error &e)
      {
        // The patient pipeline's errors about seed points, cuts and bone
        // parts end by pointing at 'softface preview SCENE.prm'
        // (Patient::preview_hint()); it does not know the scene's file.
        std::string       message     = e.what();
        const std::string placeholder = "'softface preview SCENE.prm'";
        const auto        at          = message.rfind(placeholder);
        if (at == std::string::npos)
          throw;
        message.replace(at,
                        placeholder.size(),
                        "'softface preview " + filename + "'");
        throw Error(message);
      }
    describe_scene(needs_cells, wall.wall_time(), out);
    prepare_skin(filename, out);
    prepare_outputs(out);
    write_inputs(filename, out);
    check_planning_scale(filename);
    const PlanningList &plannings = state->plannings;
    if (plannings.plans.size() > 1)
      out << "  " << plannings.plans.size()
          << " plans: every model solves each after one setup" << std::endl;
  }

  void
  Simulator::create_plugins(const std::string &filename)
  {
    ParameterHandler &prm = state->prm;
    read_parameters(filename, prm);
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    state->writes_outputs =
      Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    // A truth scene as the post-operative skin is a run of its own, whose
    // files every rank would test and remove while rank 0 writes them:
    // refused before any work.
    if (n_ranks > 1)
      {
        prm.enter_subsection("Skin");
        const std::string post_operative = prm.get("Post-operative skin");
        prm.leave_subsection();
        if (SkinParameters::names_truth_scene(post_operative))
          throw Error(filename +
                      ": Skin/Post-operative skin: a truth scene ('" +
                      post_operative + "') runs on one MPI rank only, not on " +
                      std::to_string(n_ranks) +
                      "; run it alone first and give its skin_<model>.ply.");
      }

    state->input_directory =
      std::filesystem::path(filename).parent_path().string();
    OutputParameters &output = state->output;
    output.parse_parameters(prm);
    reference     = output.reference_model;
    auto &models  = state->models;
    auto &effects = state->effects;
    try
      {
        Threads::set_limit(Models::selected_threads(prm));
        for (const std::string &name : Models::selected_names(prm))
          models.emplace_back(name, Models::create(name, prm));
        // On several ranks the distributed models share one partition of
        // the scene (Models/Partitioner), made when the first needs it.
        if (n_ranks > 1)
          {
            prm.enter_subsection("Models");
            state->layout = std::make_shared<SharedDistributedLayout>(
              MPI_COMM_WORLD,
              DistributedLayout::parse_partitioner(prm.get("Partitioner")),
              prm.get_integer("Mesh group size"));
            prm.leave_subsection();
          }
        // Every selected model must simulate every effect the scene calls
        // for; this is known before any work.
        for (const std::string &name : Effects::selected_names(prm))
          effects.emplace_back(name, Effects::create(name, prm));
        for (const auto &[model_name, model] : models)
          for (const auto &[effect_name, effect] : effects)
            Effects::check_supported(model_name,
                                     model->honoured_effects(),
                                     effect_name,
                                     *effect);
        prm.enter_subsection("Output");
        state->outputs = Outputs::create_all(prm, state->input_directory);
        prm.leave_subsection();
        if (!output.reference_model.empty())
          {
            const auto known = Models::registered_names();
            if (std::find(known.begin(), known.end(), reference) == known.end())
              throw Error("Output/Reference model: '" + reference +
                          "' is not a model ('softface --help' lists them).");
          }
      }
    catch (const Error &e)
      {
        throw Error(filename + ": " + e.what());
      }
  }

  std::string
  Simulator::build_scene(const std::string &filename, std::ostream &out)
  {
    ParameterHandler &prm     = state->prm;
    const auto       &output  = state->output;
    const auto       &models  = state->models;
    const auto       &effects = state->effects;
    out << "softface: scene " << filename << std::endl;
    const std::string &input_directory = state->input_directory;
    the_scene                          = std::make_unique<Scene>();
    Scene &scene                       = *the_scene;
    // In groups of ranks (Models/Mesh group size) whose models all read
    // nothing of the scene's cells, the members hold none: each group's
    // root reads or makes the mesh, and rank 0 sends the members the rest.
    // Vertex constraints (sliding contact, separated lips) keep every model
    // whole on every rank.
    std::string needs_cells;
    for (const auto &[name, model] : models)
      if (needs_cells.empty() && !model->runs_without_scene_cells())
        needs_cells = name;
    for (const auto &[name, effect] : effects)
      if (needs_cells.empty() &&
          (effect->contributions() & SceneEffects::free_vertex_constraints))
        needs_cells = name;
    const bool members_without_cells = state->members_without_cells =
      state->layout != nullptr && state->layout->group_size > 1 &&
      needs_cells.empty();
    const bool holds_cells = !members_without_cells ||
                             Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) %
                                 state->layout->group_size ==
                               0;
    {
      std::unique_ptr<SubCommunicator> readers;
      if (members_without_cells)
        readers =
          std::make_unique<SubCommunicator>(MPI_COMM_WORLD, holds_cells);
      scene.parse_parameters(prm,
                             input_directory,
                             output.directory + "/patient",
                             &out,
                             readers ? readers->communicator : MPI_COMM_WORLD);
    }
    // Effects that change the mesh (a slit, contact faces) do so before
    // the models see it; the DoFs and join points are then found again.
    PlanningList &plannings = state->plannings;
    try
      {
        if (scene.has_cells())
          {
            bool mesh_changed = false;
            for (const auto &[name, effect] : effects)
              {
                const std::string line = effect->prepare_mesh(scene);
                if (!line.empty())
                  out << "  effect " << line << std::endl;
                mesh_changed |= !line.empty();
              }
            if (mesh_changed)
              scene.setup();
            plannings.parse_parameters(prm, scene);
            for (const auto &[name, effect] : effects)
              {
                const std::string summary = effect->apply(scene);
                scene.effects.names.push_back(name);
                out << "  effect " << summary << std::endl;
              }
          }
        if (members_without_cells)
          {
            scene.share_without_cells(MPI_COMM_WORLD);
            if (!scene.has_cells())
              {
                plannings.parse_parameters(prm, scene);
                // The rules per cell, which each rank's effects declare
                // alike: the layout's part of the mesh applies them.
                for (const auto &[name, effect] : effects)
                  effect->declare_rules(scene);
              }
          }
      }
    catch (const Error &e)
      {
        throw Error(filename + ": " + e.what());
      }
    return needs_cells;
  }

  void
  Simulator::describe_scene(const std::string &needs_cells,
                            const double       seconds,
                            std::ostream      &out) const
  {
    const Scene       &scene = *the_scene;
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    const bool members_without_cells = state->members_without_cells;
    out << "  mesh " << scene.mesh_description << ": " << scene.n_cells()
        << " tetrahedra, " << scene.n_vertices() << " vertices, "
        << scene.n_free_dofs() << " free DoFs (" << std::fixed
        << std::setprecision(2) << seconds << " s)" << std::endl;
    for (unsigned int s = 0; s < scene.segments.size(); ++s)
      out << "  segment '" << scene.segments[s].name
          << "': " << scene.n_join_vertices(s) << " join points" << std::endl;
    if (state->layout != nullptr && state->layout->group_size > 1)
      {
        out << "  MPI ranks: " << n_ranks << " in groups of "
            << state->layout->group_size << "; "
            << (members_without_cells ?
                  "the groups' members hold none of the scene's cells" :
                  "every rank holds the scene's cells ('" + needs_cells +
                    "' needs them)")
            << std::endl;
      }
  }

  void
  Simulator::prepare_skin(const std::string &filename, std::ostream &out)
  {
    ParameterHandler  &prm             = state->prm;
    const Scene       &scene           = *the_scene;
    const auto        &output          = state->output;
    const std::string &input_directory = state->input_directory;
    // The dense skin (Skin): read and step A of its mappings before any
    // model runs, so that a skin the mesh cannot reach stops the run early.
    // The skin output keeps a reference to its parameters.
    auto           &skin            = state->skin;
    SkinParameters &skin_parameters = state->skin_parameters;
    try
      {
        std::string patient_skin;
        prm.enter_subsection("Scene");
        if (prm.get("Mesh source") == "patient")
          {
            Patient::PatientParameters patient;
            patient.parse_parameters(prm,
                                     input_directory,
                                     output.directory + "/patient");
            patient_skin = patient.work_directory + "/skin.ply";
          }
        prm.leave_subsection();
        skin_parameters.parse_parameters(prm, input_directory, patient_skin);
        if (!skin_parameters.truth_scene.empty())
          skin_parameters.post_operative_skin =
            post_operative_skin_of(skin_parameters.truth_scene, out);
        // On several ranks rank 0 alone maps and writes the skins; an error
        // it meets is met by every rank.
        if (!skin_parameters.skin_surface.empty())
          on_rank_0(MPI_COMM_WORLD, [&]() {
            skin = std::make_unique<SkinOutput>(skin_parameters,
                                                scene,
                                                output.directory,
                                                out);
          });
      }
    catch (const Error &e)
      {
        throw Error(filename + ": " + e.what());
      }
  }

  void
  Simulator::prepare_outputs(std::ostream &out)
  {
    // Only the outputs the scene asks for take part.
    auto &outputs = state->outputs;
    outputs.erase(std::remove_if(outputs.begin(),
                                 outputs.end(),
                                 [](const auto &output) {
                                   return !output->requested();
                                 }),
                  outputs.end());
    state->run = std::make_unique<Outputs::Run>(
      Outputs::Run{*the_scene,
                   model_runs,
                   reference,
                   state->output.directory,
                   state->writes_outputs,
                   state->layout.get(),
                   state->members_without_cells,
                   !state->skin_parameters.skin_surface.empty(),
                   state->skin.get()});
    for (const auto &output : outputs)
      output->prepare(*state->run, out);
  }

  void
  Simulator::write_inputs(const std::string &filename, std::ostream &out)
  {
    ParameterHandler  &prm             = state->prm;
    const Scene       &scene           = *the_scene;
    const auto        &output          = state->output;
    const std::string &input_directory = state->input_directory;
    if (state->writes_outputs)
      {
        create_output_directory(output.directory);
        std::filesystem::copy_file(
          filename,
          output.directory + "/input.prm",
          std::filesystem::copy_options::overwrite_existing);
        // Every parameter, the input files as absolute paths: the file runs
        // again from the output folder (or any other).
        make_input_files_absolute(prm, input_directory);
        std::ofstream expanded(output.directory + "/parameters.prm");
        prm.print_parameters(expanded, ParameterHandler::PRM);
      }
    // A patient's figures (voxels, tissue volumes, mesh quality, stage
    // times) for the reader and the patients benchmark.
    if (!scene.patient_figures.empty() && state->writes_outputs)
      {
        auto csv = open_output_file(output.directory + "/patient.csv");
        csv << "figure,value\n";
        for (const auto &[name, value] : scene.patient_figures)
          csv << name << ',' << value << '\n';
        csv << "shared join points," << scene.n_shared_join_points << '\n';
        out << "  patient: " << scene.n_shared_join_points
            << " vertices touching two bone parts left free; figures in "
            << output.directory << "/patient.csv" << std::endl;
      }
  }

  void
  Simulator::check_planning_scale(const std::string &filename) const
  {
    const Scene        &scene     = *the_scene;
    const PlanningList &plannings = state->plannings;
    // A join point moved by many times the mesh's size is a planning in
    // the wrong units (or a typo), not surgery: refused before any model
    // runs into overflow.
    const auto &vertices = scene.vertices();
    Point<3>    low = vertices[0], high = vertices[0];
    for (const auto &x : vertices)
      for (unsigned int d = 0; d < 3; ++d)
        {
          low[d]  = std::min(low[d], x[d]);
          high[d] = std::max(high[d], x[d]);
        }
    const double size = low.distance(high);
    for (const auto &plan : plannings.plans)
      {
        // Not kept: a sweep's plans are made again as they are solved.
        const double largest =
          plan.planning.prescribed_displacement(scene).linfty_norm();
        if (!(largest <= 10. * size))
          {
            std::ostringstream m;
            m << std::setprecision(3) << filename
              << (plannings.plans.size() > 1 ? ": plan '" + plan.name + "'" :
                                               std::string(": the planning"))
              << " moves a join point by " << largest
              << " mm, more than ten times the mesh's size (" << size
              << " mm); check Planning's translations and rotation "
              << "centres (mm).";
            throw Error(m.str());
          }
      }
  }
} // namespace softface

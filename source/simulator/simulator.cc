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
#include <softface/core/planning.h>
#include <softface/core/planning_list.h>
#include <softface/core/process.h>
#include <softface/core/scene.h>
#include <softface/core/sub_communicator.h>
#include <softface/core/threads.h>
#include <softface/effects/interface.h>
#include <softface/fe/point_evaluation.h>
#include <softface/io/output_file.h>
#include <softface/io/points_csv.h>
#include <softface/models/interface.h>
#include <softface/models/response_basis.h>
#include <softface/patient/backend.h>
#include <softface/patient/vec3_parameter.h>
#include <softface/serve/parameters.h>
#include <softface/simulator/input_files.h>
#include <softface/simulator/output.h>
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
  namespace
  {
    // What the ranks other than 0 print goes nowhere, without failing the
    // stream (deal.II's writers check it).
    class SilentBuffer : public std::streambuf
    {
    protected:
      int
      overflow(const int c) override
      {
        return traits_type::not_eof(c);
      }
    };

    // On several MPI ranks a run's times are the slowest rank's and its
    // memory the largest rank's. Collective.
    void
    take_slowest_rank(Report::ModelRun &run)
    {
      const MPI_Comm      comm  = MPI_COMM_WORLD;
      auto               &s     = run.statistics;
      std::vector<double> local = {s.setup_time,
                                   s.solve_time,
                                   run.basis_time,
                                   run.peak_memory_mb};
      // Every rank ran the same phases (the simulator checks that they
      // agree on failures); a count that differs anyway keeps this rank's.
      const unsigned int n_phases    = s.phases.size();
      const bool         same_phases = Utilities::MPI::min(n_phases, comm) ==
                               Utilities::MPI::max(n_phases, comm);
      if (same_phases)
        for (const auto &[name, seconds] : s.phases)
          local.push_back(seconds);
      std::vector<double> largest(local.size());
      Utilities::MPI::max(local, comm, largest);
      s.setup_time       = largest[0];
      s.solve_time       = largest[1];
      run.basis_time     = largest[2];
      run.peak_memory_mb = largest[3];
      if (same_phases)
        for (unsigned int p = 0; p < n_phases; ++p)
          s.phases[p].second = largest[4 + p];
    }

    struct OutputParameters
    {
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Output");
        prm.declare_entry("Output directory",
                          "output",
                          Patterns::Anything(),
                          "Folder for summary.csv, solution.vtu, the input and "
                          "the expanded parameter file (relative to the "
                          "working directory; created if missing).");
        prm.declare_entry("Write VTU",
                          "true",
                          Patterns::Bool(),
                          "Write solution.vtu: every model's displacement, the "
                          "join flag and segment id per vertex, material ids.");
        prm.declare_entry("Write nodal displacements",
                          "false",
                          Patterns::Bool(),
                          "Write displacements_<model>.csv with columns "
                          "x,y,z,ux,uy,uz (mm), one row per vertex in "
                          "reference coordinates.");
        prm.declare_entry("Reference model",
                          "linear fem",
                          Patterns::Anything(),
                          "The model every other model's displacement is "
                          "compared to in the table and summary.csv (largest "
                          "and mean difference over the free vertices). No "
                          "comparison when it is not among Models/Models or "
                          "fails.");
        prm.declare_entry(
          "Evaluation points",
          "",
          Patterns::Anything(),
          "CSV file whose first three columns are x,y,z (mm, reference "
          "configuration; a header line is skipped), e.g. the "
          "displacements_*.csv of another run. If set, every model's "
          "displacement there is written to evaluation_<model>.csv: "
          "interpolated with the model's shape functions (linear, or "
          "quadratic for 'Polynomial degree = 2'). Relative paths are "
          "taken from the parameter file's folder. Points must lie in the "
          "mesh.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Output");
        directory                 = prm.get("Output directory");
        write_vtu                 = prm.get_bool("Write VTU");
        write_nodal_displacements = prm.get_bool("Write nodal displacements");
        evaluation_points         = prm.get("Evaluation points");
        reference_model           = prm.get("Reference model");
        prm.leave_subsection();
      }

      std::string directory;
      bool        write_vtu                 = true;
      bool        write_nodal_displacements = false;
      std::string evaluation_points;
      std::string reference_model;
    };

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
        output.directory + "/skin_" + Output::file_name_of(models[0]) + ".ply";
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

    // The names a file lists in a given entry, read tolerantly (pass one).
    void
    parse_tolerantly(const std::string &filename, ParameterHandler &prm)
    {
      prm.parse_input(filename, "", /*skip_undefined=*/true);
    }

    /**
     * Follow the 'include' lines of a parameter file before deal.II does:
     * it would recurse without end on a file that includes itself. Paths
     * are read as deal.II reads them (relative to the working directory).
     */
    void
    check_includes(const std::string &filename, std::vector<std::string> chain)
    {
      constexpr unsigned int max_depth = 10;
      chain.push_back(filename);
      std::ifstream in(filename);
      std::string   line;
      for (unsigned int number = 1; std::getline(in, line); ++number)
        {
          const auto hash = line.find('#');
          if (hash != std::string::npos)
            line.erase(hash);
          line = Utilities::trim(line);
          if (line.rfind("include", 0) != 0 ||
              (line.size() > 7 && !std::isspace(line[7])))
            continue;
          const std::string included = Utilities::trim(line.substr(7));
          const std::string where =
            filename + ":" + std::to_string(number) + ": ";
          if (std::find(chain.begin(), chain.end(), included) != chain.end())
            throw Error(where + "'include " + included +
                        "' includes a file that is already being read.");
          if (chain.size() >= max_depth)
            throw Error(where + "'include' nested deeper than " +
                        std::to_string(max_depth) + " files.");
          if (!std::filesystem::is_regular_file(included) ||
              !std::ifstream(included))
            throw Error(where + "cannot open included file '" + included +
                        "'.");
          check_includes(included, chain);
        }
    }
  } // namespace

  /// What prepare() makes and run() uses.
  struct Simulator::Prepared
  {
    ParameterHandler prm;
    OutputParameters output;
    std::string      input_directory;
    std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>>
      models;
    std::vector<std::pair<std::string, std::unique_ptr<Effects::Interface>>>
                                     effects;
    PlanningList                     plannings;
    std::unique_ptr<PointEvaluation> evaluation;
    // On several MPI ranks, on every rank: the evaluation points, their
    // cells and reference coordinates, for a model whose field lives on the
    // ranks.
    std::vector<Point<3>>       evaluation_points;
    std::vector<unsigned int>   evaluation_cells;
    std::vector<Point<3>>       evaluation_reference_points;
    SkinParameters              skin_parameters;
    std::unique_ptr<SkinOutput> skin;
    // On several MPI ranks every rank runs the scene; rank 0 alone writes
    // the outputs.
    bool writes_outputs = true;
    // On several MPI ranks: the partition the distributed models share, and
    // on which the ranks write their pieces of the fields.
    std::shared_ptr<SharedDistributedLayout> layout;
    // Do the members of the groups of ranks hold no cells of the scene?
    bool members_without_cells = false;
  };

  Simulator::Simulator()  = default;
  Simulator::~Simulator() = default;

  void
  Simulator::declare_parameters(ParameterHandler               &prm,
                                const std::vector<std::string> &segment_names,
                                const std::vector<std::string> &moved_segments,
                                const std::vector<std::string> &cut_names,
                                const std::vector<std::string> &plan_names)
  {
    Scene::declare_parameters(prm, segment_names, cut_names);
    PlanningList::declare_parameters(prm, moved_segments, plan_names);
    Models::declare_parameters(prm);
    Effects::declare_parameters(prm);
    SkinParameters::declare_parameters(prm);
    OutputParameters::declare_parameters(prm);
    Serve::Parameters::declare_parameters(prm);
  }

  void
  Simulator::read_parameters(const std::string &filename, ParameterHandler &prm)
  {
    // A directory opens as a stream on Linux (and reads as empty).
    if (!std::filesystem::is_regular_file(filename) || !std::ifstream(filename))
      throw Error("Cannot open parameter file '" + filename +
                  "' (not a readable file).");
    check_includes(filename, {});

    ParameterHandler first_pass;
    declare_parameters(first_pass, {}, {});
    parse_tolerantly(filename, first_pass);

    declare_parameters(prm,
                       Scene::segment_names(first_pass),
                       Planning::moved_segment_names(first_pass),
                       Scene::cut_names(first_pass),
                       PlanningList::plan_names(first_pass));
    prm.parse_input(filename);
  }

  void
  Simulator::print_default_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    declare_parameters(prm, {"fixed", "bone"}, {"bone"});
    prm.print_parameters(out, ParameterHandler::PRM);
  }

  void
  Simulator::prepare(const std::string &filename, std::ostream &out)
  {
    Timer wall;

    state                 = std::make_unique<Prepared>();
    ParameterHandler &prm = state->prm;
    read_parameters(filename, prm);
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    state->writes_outputs =
      Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    // A truth scene as the post-operative skin is a run of its own, whose
    // files every rank would test and remove while rank 0 writes them
    // (issue 20): refused before any work.
    if (n_ranks > 1)
      {
        prm.enter_subsection("Skin");
        const std::string post_operative = prm.get("Post-operative skin");
        prm.leave_subsection();
        if (SkinParameters::names_truth_scene(post_operative))
          throw Error(
            filename + ": Skin/Post-operative skin: a truth scene ('" +
            post_operative + "') runs on one MPI rank only for now, not on " +
            std::to_string(n_ranks) +
            "; run it alone first and give its skin_<model>.ply.");
      }

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
            for (auto &model : models)
              model.second->set_shared_layout(state->layout);
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

    out << "softface: scene " << filename << std::endl;
    const std::string input_directory =
      std::filesystem::path(filename).parent_path().string();
    state->input_directory = input_directory;
    the_scene              = std::make_unique<Scene>();
    Scene &scene           = *the_scene;
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
              plannings.parse_parameters(prm, scene);
          }
      }
    catch (const Error &e)
      {
        throw Error(filename + ": " + e.what());
      }

    out << "  mesh " << scene.mesh_description << ": " << scene.n_cells()
        << " tetrahedra, " << scene.n_vertices() << " vertices, "
        << scene.n_free_dofs() << " free DoFs (" << std::fixed
        << std::setprecision(2) << wall.wall_time() << " s)" << std::endl;
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

    auto &evaluation = state->evaluation;
    if (!output.evaluation_points.empty())
      {
        std::filesystem::path points_file(output.evaluation_points);
        if (points_file.is_relative() && !input_directory.empty())
          points_file = std::filesystem::path(input_directory) / points_file;
        // Rank 0 reads them (its error is every rank's) and sends them.
        std::vector<Point<3>> points;
        on_rank_0(MPI_COMM_WORLD,
                  [&]() { points = read_points_csv(points_file.string()); });
        if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
          points = Utilities::MPI::broadcast(MPI_COMM_WORLD, points);
        try
          {
            // Rank 0 writes the values (and may be the only rank with the
            // cells); its error is every rank's.
            on_rank_0(MPI_COMM_WORLD, [&]() {
              evaluation =
                std::make_unique<PointEvaluation>(scene.triangulation, points);
            });
          }
        catch (const Error &e)
          {
            throw Error("Output/Evaluation points '" + points_file.string() +
                        "': " + e.what());
          }
        if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
          {
            state->evaluation_points = points;
            if (evaluation)
              {
                state->evaluation_cells = evaluation->cell_indices();
                state->evaluation_reference_points =
                  evaluation->reference_coordinates();
              }
            state->evaluation_cells =
              Utilities::MPI::broadcast(MPI_COMM_WORLD,
                                        state->evaluation_cells);
            state->evaluation_reference_points =
              Utilities::MPI::broadcast(MPI_COMM_WORLD,
                                        state->evaluation_reference_points);
          }
        out << "  " << points.size() << " evaluation points from "
            << points_file.string() << std::endl;
      }

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

    {
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
    if (plannings.plans.size() > 1)
      out << "  " << plannings.plans.size()
          << " plans: every model solves each after one setup" << std::endl;
  }

  int
  Simulator::run(const std::string &filename,
                 std::ostream      &out_of_rank_0,
                 std::ostream      &err_of_rank_0)
  {
    // On several MPI ranks, rank 0 speaks for all: they take the same
    // decisions on the same scene.
    SilentBuffer discard;
    std::ostream silent(&discard);
    const bool   speaks = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    std::ostream      &out = speaks ? out_of_rank_0 : silent;
    std::ostream      &err = speaks ? err_of_rank_0 : silent;
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    prepare(filename, out);
    const bool writes = state->writes_outputs;
    // Ranks that disagree on whether a model failed have left the same
    // path: the job cannot go on (main() ends it).
    const auto same_on_every_rank = [&](const bool         failed,
                                        const std::string &what) {
      if (n_ranks > 1 && Utilities::MPI::min(int(failed), MPI_COMM_WORLD) !=
                           Utilities::MPI::max(int(failed), MPI_COMM_WORLD))
        throw Error(what +
                    (failed ? " failed on this rank and not on others" :
                              " failed on other ranks and not on this one") +
                    "; the ranks cannot go on together.");
    };
    Scene      &scene     = *the_scene;
    const auto &output    = state->output;
    auto       &models    = state->models;
    const auto &plannings = state->plannings;
    const auto &skin      = state->skin;
    // Every rank knows whether the run maps skins (rank 0 maps them).
    const bool  maps_skins     = !state->skin_parameters.skin_surface.empty();
    const auto &evaluation     = state->evaluation;
    const unsigned int n_plans = plannings.plans.size();

    // A model that fails (no convergence, a motion it cannot follow) is
    // reported and left out; the others still run, and the exit code says
    // that something failed.
    model_runs.clear();
    unsigned int n_failed = 0;
    for (unsigned int m = 0; m < models.size(); ++m)
      {
        auto &[name, model]   = models[m];
        const std::string tag = "  [" + std::to_string(m + 1) + '/' +
                                std::to_string(models.size()) + "] " + name +
                                ": ";
        // (@p where empty: said once already, for the model's first plan.)
        const auto record_failure = [&](Report::ModelRun     &run,
                                        const std::string    &where,
                                        const std::exception &e) {
          // On several ranks only softface's own errors, which every rank
          // meets alike (they hold the same scene), are a model's failure;
          // anything else (memory, a library's exception) may be one rank's,
          // with the others waiting in a collective: main() ends the job.
          if (n_ranks > 1 && dynamic_cast<const Error *>(&e) == nullptr)
            throw;
          run.failed = true;
          run.error  = error_message(e);
          run.displacement.reinit(0);
          ++n_failed;
          if (where.empty())
            return;
          out << where << "failed" << std::endl;
          err << "softface: error: " + run.error + '\n' << std::flush;
        };
        // The answer of an earlier model to plan p that @p wanted accepts
        // (every earlier model has a run per plan, in order), or nullptr.
        const auto earlier_answer =
          [&](const unsigned int                                   p,
              const std::function<bool(const Report::ModelRun &)> &wanted)
          -> const Vector<double> * {
          for (std::size_t r = p; r < model_runs.size(); r += n_plans)
            if (!model_runs[r].failed && wanted(model_runs[r]))
              return &model_runs[r].displacement;
          return nullptr;
        };
        const auto plan_of_run = [&](const unsigned int p) {
          return n_plans > 1 ? plannings.plans[p].name : std::string();
        };

        // One setup for every plan; a model linear in the motion may then
        // build its response basis, and each plan is a combination.
        Models::ResponseBasis basis;
        bool                  use_basis  = false;
        double                basis_time = 0.;
        Models::Statistics    after_setup;
        std::exception_ptr    setup_error;
        try
          {
            model->set_progress_stream(&out);
            model->setup(scene);
            after_setup = model->statistics();
            out << tag << "setup " << after_setup.setup_time << " s"
                << std::endl;
            const auto moved = plannings.plans[0].planning.moved_segments();
            const unsigned int n_basis_solves =
              Models::ResponseBasis::n_solves(scene, moved.size());
            use_basis = model->linear_in_motion(scene) &&
                        (plannings.basis == PlanningList::Basis::always ||
                         (plannings.basis == PlanningList::Basis::automatic &&
                          n_plans > n_basis_solves));
            if (use_basis)
              {
                Timer timer;
                model->set_progress_stream(nullptr);
                basis.build(*model, scene, moved);
                model->set_progress_stream(&out);
                basis_time = timer.wall_time();
                out << tag << "response basis " << basis_time << " s ("
                    << n_basis_solves << " solves, " << std::setprecision(3)
                    << basis.memory_mb() << " MB)" << std::endl;
              }
          }
        catch (const std::exception &e)
          {
            if (n_ranks > 1 && dynamic_cast<const Error *>(&e) == nullptr)
              throw; // see record_failure()
            setup_error = std::current_exception();
          }
        same_on_every_rank(setup_error != nullptr, name + "'s setup");
        if (setup_error)
          {
            // Setup failed: so does every plan.
            try
              {
                std::rethrow_exception(setup_error);
              }
            catch (const std::exception &e)
              {
                for (unsigned int p = 0; p < n_plans; ++p)
                  {
                    Report::ModelRun run;
                    run.model    = name;
                    run.planning = plan_of_run(p);
                    record_failure(run, p == 0 ? tag : std::string(), e);
                    model_runs.push_back(std::move(run));
                  }
              }
            model.reset();
            continue;
          }

        for (unsigned int p = 0; p < n_plans; ++p)
          {
            const auto      &plan = plannings.plans[p];
            Report::ModelRun run;
            run.model               = name;
            run.planning            = plan_of_run(p);
            run.basis_time          = basis_time;
            const std::string where = n_plans > 1 ?
                                        tag + "plan " + std::to_string(p + 1) +
                                          '/' + std::to_string(n_plans) + " '" +
                                          plan.name + "': " :
                                        tag;
            try
              {
                if (use_basis)
                  {
                    Timer timer;
                    basis.combine(plan.planning, run.displacement);
                    run.statistics            = after_setup;
                    run.statistics.solve_time = timer.wall_time();
                    run.statistics.residual   = basis.largest_residual;
                    run.statistics.phases.emplace_back("response basis",
                                                       basis_time);
                    run.statistics.phases.emplace_back(
                      "combination", run.statistics.solve_time);
                    run.statistics.details.push_back(
                      {"basis iterations",
                       double(basis.total_iterations),
                       "",
                       ""});
                    run.statistics.details.push_back(
                      {"basis memory", basis.memory_mb(), "", "MB"});
                    for (const auto &warning : basis.warnings)
                      run.statistics.warnings.push_back("response basis: " +
                                                        warning);
                  }
                else
                  {
                    model->set_load_path([&plan, &scene](const double load) {
                      return plan.planning.prescribed_displacement(scene, load);
                    });
                    // A model that ran this plan from its response basis
                    // offers its answer as a start (the nonlinear models
                    // take it); the model that solves this one's equations
                    // exactly, its answer.
                    model->set_initial_guess(
                      earlier_answer(p, [](const Report::ModelRun &r) {
                        return r.basis_time > 0.;
                      }));
                    const std::string equivalent =
                      model->converged_equivalent();
                    model->set_converged_answer(
                      earlier_answer(p, [&](const Report::ModelRun &r) {
                        return r.model == equivalent;
                      }));
                    model->solve(plan.planning.prescribed_displacement(scene),
                                 run.displacement);
                    model->set_initial_guess(nullptr);
                    model->set_converged_answer(nullptr);
                    run.statistics = model->statistics();
                  }
                // Overflowing inputs (moduli or loads far out of range) or
                // a solve that broke down must not pass as an answer.
                for (const double value : run.displacement)
                  if (!std::isfinite(value))
                    throw Error(name +
                                ": the displacement is not finite (NaN or "
                                "infinite): the solve broke down or the "
                                "inputs (moduli, loads) are far out of "
                                "range.");
                run.max_displacement =
                  Displacement::max_norm(scene, run.displacement);
                out << where << (use_basis ? "combination " : "solve ")
                    << run.statistics.solve_time << " s" << std::endl;
                // Rank 0 maps for all; its error is every rank's.
                if (maps_skins)
                  on_rank_0(MPI_COMM_WORLD, [&]() {
                    skin->add_model(run.label(), scene, run.displacement);
                  });
                for (const auto &warning : run.statistics.warnings)
                  err << "softface: warning: " << run.label() << ": " << warning
                      << std::endl;
                if (!output.evaluation_points.empty())
                  {
                    // A field on the ranks' parts of the mesh (the
                    // quadratic reference there) is evaluated by all ranks.
                    std::vector<Tensor<1, 3>> values;
                    const bool on_ranks = !use_basis && n_ranks > 1 &&
                                          model->displacement_field_at(
                                            state->evaluation_points,
                                            state->evaluation_cells,
                                            state->evaluation_reference_points,
                                            values);
                    const auto [field_dofs, field] =
                      model->displacement_field();
                    if (evaluation && writes)
                      write_point_values_csv(
                        evaluation->points(),
                        on_ranks ? values :
                        field_dofs != nullptr && !use_basis ?
                                   evaluation->evaluate(*field_dofs, *field) :
                                   evaluation->evaluate(scene.dof_handler,
                                                        run.displacement),
                        output.directory + "/evaluation_" +
                          Output::file_name_of(run.label()) + ".csv");
                  }
              }
            catch (const std::exception &e)
              {
                record_failure(run, where, e);
              }
            Utilities::System::MemoryStats memory;
            Utilities::System::get_memory_stats(memory);
            run.peak_memory_mb = memory.VmHWM / 1024.;
            if (n_ranks > 1)
              {
                same_on_every_rank(run.failed, run.label() + "'s solve");
                take_slowest_rank(run);
              }
            model_runs.push_back(std::move(run));
          }
        // The model's memory is freed once it has run; the peak stays.
        model.reset();
      }

    Report::compare_to(scene, reference, model_runs);
    out << '\n';
    Report::print(scene, model_runs, reference, true, out);
    if (writes)
      {
        if (skin)
          skin->write(out);
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
        << (evaluation ? ", evaluation_*.csv" : "")
        << (skin ? ", skin.csv, skin_*.ply/.vtp" : "")
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
    if (n_failed > 0)
      {
        std::string names;
        for (const auto &run : model_runs)
          if (run.failed)
            names += (names.empty() ? "" : ", ") + run.label();
        err << "softface: " << n_failed
            << (n_plans > 1 ? " run(s) failed: " : " model(s) failed: ")
            << names << std::endl;
        return 1;
      }
    return 0;
  }

  int
  Simulator::run_patient_stages(const std::string &filename,
                                const std::string &stage,
                                std::ostream      &out)
  {
    ParameterHandler prm;
    read_parameters(filename, prm);
    OutputParameters output;
    output.parse_parameters(prm);
    const std::string input_directory =
      std::filesystem::path(filename).parent_path().string();

    Patient::PatientParameters        patient;
    std::vector<Patient::SegmentSeed> seeds;
    prm.enter_subsection("Scene");
    if (prm.get("Mesh source") != "patient")
      throw Error(filename + ": 'softface " + stage +
                  "' runs the patient stages of a scene with 'Scene/Mesh "
                  "source = patient'.");
    patient.parse_parameters(prm,
                             input_directory,
                             output.directory + "/patient");
    for (const std::string &name :
         Utilities::split_string_list(prm.get("Bone segments")))
      {
        prm.enter_subsection("Segment " + name);
        const std::string point = prm.get("Seed point");
        prm.leave_subsection();
        if (point.empty())
          throw Error("Scene/Segment " + name +
                      ": a patient scene's segment needs a 'Seed point' "
                      "'x, y, z' in its bone.");
        seeds.push_back(
          {name,
           Patient::parse_vec3(point,
                               "Scene/Segment " + name + "/Seed point")});
      }
    prm.leave_subsection();

    out << "softface " << stage << ": " << filename << std::endl;
    Timer wall;
    if (stage == "register")
      {
        Patient::backend().register_post_operative(patient,
                                                   output.directory,
                                                   out);
        return 0;
      }
    if (stage == "postop" || stage == "plan")
      return plan_from_skull(prm, filename, stage, patient, seeds, out);
    const auto model =
      Patient::backend().build_patient_model(patient,
                                             seeds,
                                             stage == "phantom" ?
                                               Patient::Stage::phantom :
                                               (stage == "segment" ?
                                                  Patient::Stage::segmentation :
                                                  Patient::Stage::mesh),
                                             out);
    for (const auto &[name, value] : model.figures)
      out << "  " << name << ": " << value << '\n';
    out << "Files in " << patient.work_directory << "/ (wall time "
        << std::fixed << std::setprecision(1) << wall.wall_time() << " s)"
        << std::endl;
    return 0;
  }

  int
  Simulator::plan_from_skull(ParameterHandler                        &prm,
                             const std::string                       &filename,
                             const std::string                       &stage,
                             const Patient::PatientParameters        &patient,
                             const std::vector<Patient::SegmentSeed> &seeds,
                             std::ostream                            &out)
  {
    Scene scene;
    scene.parse_parameters(
      prm,
      std::filesystem::path(filename).parent_path().string(),
      patient.work_directory,
      &out);
    Planning planning;
    planning.parse_parameters(prm, scene);

    // The scene's planning as rigid transforms x -> R x + t.
    std::vector<Patient::RigidTransform> planned;
    for (unsigned int s = 0; s < scene.segments.size(); ++s)
      {
        const RigidMotion       motion = planning.motion(s);
        const Point<3>          t      = motion(Point<3>());
        Patient::RigidTransform transform;
        for (unsigned int d = 0; d < 3; ++d)
          {
            transform.translation[d] = t[d];
            Point<3> e;
            e[d]                 = 1.;
            const Point<3> image = motion(e);
            for (unsigned int r = 0; r < 3; ++r)
              transform.rotation[3 * r + d] = image[r] - t[r];
          }
        planned.push_back(transform);
      }
    return Patient::backend().skull_stage(patient, seeds, planned, stage, out);
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

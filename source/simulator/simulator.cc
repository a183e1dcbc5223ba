#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/models/interface.h>
#include <softface/simulator/output.h>
#include <softface/core/planning.h>
#include <softface/fe/point_evaluation.h>
#include <softface/io/points_csv.h>
#include <softface/core/scene.h>
#include <softface/simulator/simulator.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

namespace softface
{
  namespace
  {
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
        prm.leave_subsection();
      }

      std::string directory;
      bool        write_vtu                 = true;
      bool        write_nodal_displacements = false;
      std::string evaluation_points;
    };

    // The names a file lists in a given entry, read tolerantly (pass one).
    void
    parse_tolerantly(const std::string &filename, ParameterHandler &prm)
    {
      prm.parse_input(filename, "", /*skip_undefined=*/true);
    }
  } // namespace

  void
  Simulator::declare_parameters(ParameterHandler               &prm,
                                const std::vector<std::string> &segment_names,
                                const std::vector<std::string> &moved_segments)
  {
    Scene::declare_parameters(prm, segment_names);
    Planning::declare_parameters(prm, moved_segments);
    Models::declare_parameters(prm);
    OutputParameters::declare_parameters(prm);
  }

  void
  Simulator::read_parameters(const std::string &filename, ParameterHandler &prm)
  {
    if (!std::ifstream(filename))
      throw Error("Cannot open parameter file '" + filename + "'.");

    ParameterHandler first_pass;
    declare_parameters(first_pass, {}, {});
    parse_tolerantly(filename, first_pass);

    declare_parameters(prm,
                       Scene::segment_names(first_pass),
                       Planning::moved_segment_names(first_pass));
    prm.parse_input(filename);
  }

  void
  Simulator::print_default_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    declare_parameters(prm, {"fixed", "bone"}, {"bone"});
    prm.print_parameters(out, ParameterHandler::PRM);
  }

  int
  Simulator::run(const std::string &filename)
  {
    Timer wall;

    ParameterHandler prm;
    read_parameters(filename, prm);

    OutputParameters output;
    output.parse_parameters(prm);
    std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>>
      models;
    for (const std::string &name : Models::selected_names(prm))
      models.emplace_back(name, Models::create(name, prm));

    std::cout << "softface: scene " << filename << std::endl;
    const std::string input_directory =
      std::filesystem::path(filename).parent_path().string();
    Scene scene;
    scene.parse_parameters(prm, input_directory);
    Planning planning;
    planning.parse_parameters(prm, scene);

    std::cout << "  mesh " << scene.mesh_description << ": "
              << scene.triangulation.n_active_cells() << " tetrahedra, "
              << scene.n_vertices() << " vertices, " << scene.n_free_dofs()
              << " free DoFs (" << std::fixed << std::setprecision(2)
              << wall.wall_time() << " s)" << std::endl;
    for (unsigned int s = 0; s < scene.segments.size(); ++s)
      std::cout << "  segment '" << scene.segments[s].name
                << "': " << scene.n_join_vertices(s) << " join points"
                << std::endl;

    std::unique_ptr<PointEvaluation> evaluation;
    if (!output.evaluation_points.empty())
      {
        std::filesystem::path points_file(output.evaluation_points);
        if (points_file.is_relative() && !input_directory.empty())
          points_file = std::filesystem::path(input_directory) / points_file;
        const auto points = read_points_csv(points_file.string());
        try
          {
            evaluation =
              std::make_unique<PointEvaluation>(scene.triangulation, points);
          }
        catch (const Error &e)
          {
            throw Error("Output/Evaluation points '" + points_file.string() +
                        "': " + e.what());
          }
        std::cout << "  " << evaluation->points().size()
                  << " evaluation points from " << points_file.string()
                  << std::endl;
      }

    std::filesystem::create_directories(output.directory);
    std::filesystem::copy_file(
      filename,
      output.directory + "/input.prm",
      std::filesystem::copy_options::overwrite_existing);
    {
      std::ofstream expanded(output.directory + "/parameters.prm");
      prm.print_parameters(expanded, ParameterHandler::PRM);
    }

    const Vector<double> prescribed = planning.prescribed_displacement(scene);


    // A model that fails (no convergence, a motion it cannot follow) is
    // reported and left out; the others still run, and the exit code says
    // that something failed.
    std::vector<Output::ModelRun> runs;
    std::vector<std::string>      failures;
    for (unsigned int m = 0; m < models.size(); ++m)
      {
        auto &[name, model] = models[m];
        const std::string tag =
          "  [" + std::to_string(m + 1) + '/' + std::to_string(models.size()) +
          "] " + name + ": ";
        try
          {
            model->setup(scene);
            std::cout << tag << "setup " << model->statistics().setup_time
                      << " s" << std::endl;
            model->set_progress_stream(&std::cout);
            Output::ModelRun run;
            run.model = name;
            model->solve(prescribed, run.displacement);
            run.statistics = model->statistics();
            std::cout << tag << "solve " << run.statistics.solve_time << " s"
                      << std::endl;
            if (evaluation)
              {
                const auto [field_dofs, field] = model->displacement_field();
                write_point_values_csv(
                  evaluation->points(),
                  field_dofs != nullptr ?
                    evaluation->evaluate(*field_dofs, *field) :
                    evaluation->evaluate(scene.dof_handler, run.displacement),
                  output.directory + "/evaluation_" +
                    Output::file_name_of(name) + ".csv");
              }
            runs.push_back(std::move(run));
          }
        catch (const Error &e)
          {
            std::cout << tag << "failed" << std::endl;
            std::cerr << "softface: error: " << e.what() << std::endl;
            failures.push_back(name);
          }
      }

    Output::compare_to_linear_fem(scene, runs);
    Output::print_summary_table(scene, runs, std::cout);
    Output::write_summary_csv(scene, runs, output.directory + "/summary.csv");
    if (output.write_vtu)
      Output::write_vtu(scene, runs, output.directory + "/solution.vtu");
    if (output.write_nodal_displacements)
      for (const auto &run : runs)
        Output::write_nodal_displacements(scene,
                                          run.displacement,
                                          output.directory + "/displacements_" +
                                            Output::file_name_of(run.model) +
                                            ".csv");

    Utilities::System::MemoryStats memory;
    Utilities::System::get_memory_stats(memory);
    std::cout << "\nOutputs in " << output.directory << "/ (summary.csv"
              << (output.write_vtu ? ", solution.vtu" : "")
              << (output.write_nodal_displacements ? ", displacements_*.csv" :
                                                     "")
              << ", input.prm, parameters.prm)\n"
              << "Wall time " << std::setprecision(2) << wall.wall_time()
              << " s, peak memory " << memory.VmHWM / 1024 << " MB"
              << std::endl;
    if (!failures.empty())
      {
        std::string names;
        for (const auto &f : failures)
          names += (names.empty() ? "" : ", ") + f;
        std::cerr << "softface: " << failures.size()
                  << " model(s) failed: " << names << std::endl;
        return 1;
      }
    return 0;
  }
} // namespace softface

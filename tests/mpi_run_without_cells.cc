// A scene run by the simulator on several MPI ranks in groups of two whose
// members hold none of the scene's cells, by ctest on 2, 3 and 4
// ranks (mpi_run_without_cells.mpirun=N.output; on 4 a root other than rank
// 0 has a member): only each group's root reads the mesh (the gmsh cube);
// a member's scene has no cells but the same counts, vertices, DoFs,
// segments, join points, effects' rules and body force as rank 0's; linear
// FEM's answer to each plan (by the response basis) and nonlinear FEM's
// (by Newton) equal the serial models' on rank 0's scene to 1e-8 relative
// and are the same on every rank; the fields written from the ranks' parts
// read back as the serial solution.vtu; rank 0 evaluates the points.
// Then the quadratic reference alone on a coarser gmsh mesh: its DoFs live on
// the ranks' parts, so its members hold no cells either; its vertex values
// and its field at the evaluation points (each point evaluated by the rank
// that owns its cell; one on a face between rank 0's and rank 1's cells,
// whose value a second evaluation would double) equal the serial
// reference's. Then the mass tensor
// and mass spring models alone on that mesh: their members hold no cells
// (rank 0 sends the tetrahedra), and their answers and sweeps are the
// serial models'. On 3 and 4 ranks, last:
// a root that reads another mesh (another file of the same name on its node)
// stops every rank with one message.

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/planning_list.h>
#include <softface/fe/point_evaluation.h>
#include <softface/io/points_csv.h>
#include <softface/simulator/simulator.h>

#include "mpi_runs.h"
#include "scenes.h"
#include "tests.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <vector>

using namespace softface_tests;

namespace
{
  // The values x,y,z,ux,uy,uz of an evaluation_*.csv (rows of six).
  std::vector<double>
  read_evaluation_csv(const std::string &file)
  {
    std::ifstream       in(file);
    std::string         line;
    std::vector<double> values;
    std::getline(in, line); // the header
    while (std::getline(in, line))
      {
        std::istringstream row(line);
        std::string        value;
        while (std::getline(row, value, ','))
          values.push_back(std::stod(value));
      }
    return values;
  }

  // Run @p run on every rank of @p comm: it says so, and its answer is
  // rank 0's on every rank.
  void
  check_ran_on_the_ranks(const std::string      &what,
                         const Report::ModelRun &run,
                         const MPI_Comm          comm)
  {
    check_equal(what + "ran on the ranks",
                ran_on_the_ranks(run, Utilities::MPI::n_mpi_processes(comm)),
                true);
    check_equal(
      what + "ranks unlike rank 0: answer",
      ranks_unlike_rank_0(std::vector<double>(run.displacement.begin(),
                                              run.displacement.end()),
                          comm),
      0);
  }

  // Runs mpi_run_without_cells.prm on the off-centre case's coarse gmsh
  // mesh (5092 cells) with @p settings, in groups of two, and checks what
  // every such run must show (under @p label): every rank ends well, only
  // the groups' roots hold cells, and rank 0 says so.
  void
  run_on_coarse_mesh(const MPI_Comm     comm,
                     const std::string &name,
                     const std::string &folder,
                     const std::string &settings,
                     const std::string &label,
                     Simulator         &simulator)
  {
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const std::string  file =
      rank_scene(comm,
                 "mpi_run_without_cells.prm",
                 name,
                 folder,
                 "subsection Scene\n  set Mesh file = " +
                   source_file("data/offcentre_coarse/mesh.msh") + "\nend\n" +
                   settings);
    std::ostringstream log, errors;
    const int          rc = simulator.run(file, log, errors);
    deallog << label << ":" << std::endl;
    check_equal("  largest exit code over the ranks",
                Utilities::MPI::max(rc, comm),
                0);
    const Scene &scene = simulator.scene();
    check_equal("  ranks that hold the scene's cells",
                Utilities::MPI::sum(int(scene.has_cells()), comm),
                (n_ranks + 1) / 2);
    check_equal("  ranks with triangulation cells but no cells said",
                Utilities::MPI::sum(int(!scene.has_cells() &&
                                        scene.triangulation.n_cells() > 0),
                                    comm),
                0);
    check_equal("  rank 0 says the members hold no cells",
                Utilities::MPI::this_mpi_process(comm) != 0 ||
                  log.str().find("the groups' members hold none of the "
                                 "scene's cells") != std::string::npos,
                true);
    check_equal("  cells (rank 0)", scene.n_cells(), 5092);
  }

  // The quadratic reference alone, in groups of two, on the off-centre
  // case's coarse gmsh mesh (5092 cells).
  void
  check_reference_without_cells(const std::string &stem, const MPI_Comm comm)
  {
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
    const std::string  name    = stem + "reference_" + std::to_string(rank);
    const std::string  folder  = name + "_output";
    // The points of run_evaluation_points.csv and the centre of a face
    // between a cell of rank 0 and one of rank 1 (the partition is the
    // cells' order in ranges), whose value must come from one rank only.
    const std::string points_file = stem + "reference_points.csv";
    bool              face_found  = false;
    if (rank == 0)
      {
        Triangulation<3> mesh;
        Mesh::read_file(source_file("data/offcentre_coarse/mesh.msh"), mesh);
        const auto owners =
          cell_owners(mesh,
                      n_ranks,
                      DistributedLayout::Partitioner::cell_order);
        Point<3> face_centre;
        for (const auto &cell : mesh.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            if (!face_found && !cell->at_boundary(f) &&
                owners[cell->active_cell_index()] == 0 &&
                owners[cell->neighbor(f)->active_cell_index()] == 1)
              {
                face_centre = cell->face(f)->center();
                face_found  = true;
              }
        std::ifstream in(source_file("data/points/run_evaluation_points.csv"));
        std::ostringstream points;
        points << in.rdbuf();
        std::string text = points.str();
        if (!text.empty() && text.back() != '\n')
          text += '\n';
        std::ofstream out(points_file);
        out << text << std::setprecision(17) << face_centre[0] << ','
            << face_centre[1] << ',' << face_centre[2] << '\n';
      }
    Simulator simulator;
    run_on_coarse_mesh(comm,
                       name,
                       folder,
                       "subsection Output\n  set Evaluation points = " +
                         points_file +
                         "\nend\nsubsection Models\n  set Models = "
                         "reference fem\nend\n",
                       "reference fem",
                       simulator);
    const Scene &scene = simulator.scene();
    if (rank == 0)
      check_equal("  an evaluation point on a face between rank 0's and "
                  "rank 1's cells",
                  face_found,
                  true);

    const auto &runs = simulator.runs();
    check_equal("  model runs (two plans)", runs.size(), 2);
    for (unsigned int p = 0; p < runs.size() && p < 2; ++p)
      {
        const std::string what = "  plan " + std::to_string(p + 1) + ": ";
        check_ran_on_the_ranks(what, runs[p], comm);
        if (rank != 0)
          continue;
        // The serial reference on rank 0's scene, and its quadratic field
        // at the points.
        const Vector<double> prescribed =
          simulator.plannings().plans[p].planning.prescribed_displacement(
            scene);
        auto model = Models::create("reference fem", simulator.parameters());
        model->setup(scene, {nullptr, MPI_COMM_SELF, nullptr});
        Vector<double> serial;
        model->solve(prescribed, serial);
        check_below(what + "relative difference to the serial model",
                    relative_difference(runs[p].displacement, serial),
                    1e-8);
        check_above(what + "largest |u_i| (mm)",
                    runs[p].displacement.linfty_norm(),
                    2.9);
        const PointEvaluation evaluation(scene.triangulation,
                                         read_points_csv(points_file));
        const auto [field_dofs, field] = model->displacement_field();
        const auto quadratic = evaluation.evaluate(*field_dofs, *field);
        const auto linear    = evaluation.evaluate(scene.dof_handler, serial);
        const std::vector<double> written = read_evaluation_csv(
          folder + "/evaluation_reference_fem_" +
          std::string(p == 0 ? "planning" : "back") + ".csv");
        check_equal(what + "evaluation values written (six per point)",
                    written.size(),
                    6 * quadratic.size());
        // The ranks that own the points' cells (the partition is the cells'
        // order in ranges): not rank 0 alone.
        const auto owners =
          cell_owners(scene.triangulation,
                      n_ranks,
                      DistributedLayout::Partitioner::cell_order);
        std::set<unsigned int> evaluating;
        for (const unsigned int c : evaluation.cell_indices())
          evaluating.insert(owners[c]);
        check_above(what + "ranks that evaluate a point", evaluating.size(), 2);
        double largest = 0., to_quadratic = 0., quadratic_to_linear = 0.;
        for (unsigned int q = 0; q < quadratic.size(); ++q)
          for (unsigned int d = 0; d < 3 && 6 * q + 5 < written.size(); ++d)
            {
              largest = std::max(largest, std::abs(quadratic[q][d]));
              to_quadratic =
                std::max(to_quadratic,
                         std::abs(written[6 * q + 3 + d] - quadratic[q][d]));
              quadratic_to_linear =
                std::max(quadratic_to_linear,
                         std::abs(linear[q][d] - quadratic[q][d]));
            }
        check_below(what + "evaluation points, largest difference to the "
                           "serial quadratic field / its largest value",
                    to_quadratic / largest,
                    1e-8);
        // What the comparison tells apart: the vertex values interpolated
        // linearly miss the quadratic field by far more.
        check_above(what + "the same for the linear interpolation of the "
                           "vertex values",
                    quadratic_to_linear / largest,
                    1e-4);
      }
  }

  // The mass tensor and mass spring models alone, in groups of two, on the
  // off-centre case's coarse gmsh mesh: the members get the tetrahedra
  // from rank 0 (PointMesh) and hold no cells.
  void
  check_point_models_without_cells(const std::string &stem, const MPI_Comm comm)
  {
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
    const std::string  name    = stem + "points_" + std::to_string(rank);
    const std::string  folder  = name + "_output";
    // Each plan solved on its own (no response basis), as the serial
    // models below solve it; the mass tensor model's precision against its
    // converged answer, which the members solve from the points alone.
    Simulator simulator;
    run_on_coarse_mesh(comm,
                       name,
                       folder,
                       "subsection Planning\n  set Response basis = "
                       "never\nend\nsubsection Models\n  set Models = mass "
                       "tensor, mass spring\n  subsection mass tensor\n    "
                       "set Report precision = true\n  end\nend\n",
                       "mass tensor and mass spring",
                       simulator);
    const Scene &scene = simulator.scene();

    const auto &runs = simulator.runs();
    check_equal("  model runs (two models, two plans)", runs.size(), 4);
    // The serial models on rank 0's scene, each plan in turn on one model
    // (the mass spring model starts the second plan from the first's).
    std::unique_ptr<Models::Interface> serial_model;
    const auto precision = [](const Models::Statistics &statistics) {
      for (const auto &detail : statistics.details)
        if (detail.name == "precision max")
          return detail.value;
      return -1.;
    };
    for (unsigned int r = 0; r < runs.size() && r < 4; ++r)
      {
        const std::string model_name = r < 2 ? "mass tensor" : "mass spring";
        const std::string what =
          "  " + model_name + ", plan " + std::to_string(r % 2 + 1) + ": ";
        check_ran_on_the_ranks(what, runs[r], comm);
        // Each rank measures the precision against the converged answer
        // it solved itself (a member from its points alone).
        if (r < 2)
          check_equal(what + "ranks unlike rank 0: precision",
                      ranks_unlike_rank_0(std::vector<double>{precision(
                                            runs[r].statistics)},
                                          comm),
                      0);
        if (rank != 0)
          continue;
        if (r % 2 == 0)
          {
            serial_model = Models::create(model_name, simulator.parameters());
            serial_model->setup(scene, {nullptr, MPI_COMM_SELF, nullptr});
          }
        Vector<double> serial;
        serial_model->solve(
          simulator.plannings().plans[r % 2].planning.prescribed_displacement(
            scene),
          serial);
        // The ranks sweep in the serial order: the serial answer and sweeps.
        check_below(what + "largest difference to the serial model (mm)",
                    largest_difference(runs[r].displacement, serial),
                    1e-12);
        check_equal(what + "sweeps (or load steps' sweeps) against serial",
                    runs[r].statistics.iterations,
                    serial_model->statistics().iterations);
        if (r < 2)
          {
            // Rank 0's figure against the serial one.
            check_above(what + "precision (mm)",
                        precision(runs[r].statistics),
                        1e-6);
            check_below(what + "precision, difference to the serial model's "
                               "(mm)",
                        std::abs(precision(runs[r].statistics) -
                                 precision(serial_model->statistics())),
                        1e-12);
          }
        check_above(what + "largest |u_i| (mm)",
                    runs[r].displacement.linfty_norm(),
                    3.);
      }
    MPI_Barrier(comm);
    if (rank == 0)
      check_fields_against_serial(folder,
                                  scene,
                                  runs,
                                  n_ranks,
                                  {"displacement_mass_tensor_planning",
                                   "displacement_mass_tensor_back",
                                   "displacement_mass_spring_planning",
                                   "displacement_mass_spring_back",
                                   "join_point",
                                   "segment_id"});
  }

  // Rank 2, the second group's root, reads the coarse mesh where rank 0
  // reads the cube: their fingerprints differ, and every rank stops.
  void
  check_roots_with_different_meshes(const std::string &stem,
                                    const MPI_Comm     comm)
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
    const std::string  name = stem + "meshes_" + std::to_string(rank);
    const std::string  file =
      rank_scene(comm,
                 "mpi_run_without_cells.prm",
                 name,
                 name + "_output",
                 "subsection Scene\n  set Mesh file = " +
                   source_file(rank == 2 ? "data/offcentre_coarse/mesh.msh" :
                                           "data/cube30k/mesh.msh") +
                   "\nend\n");
    std::ostringstream log, errors;
    Simulator          simulator;
    std::string        message;
    try
      {
        simulator.run(file, log, errors);
      }
    catch (const std::exception &e)
      {
        message = e.what();
      }
    deallog << "the second root reads another mesh:" << std::endl;
    check_equal("  ranks whose run stops with the message",
                Utilities::MPI::sum(
                  int(message.find("the roots of the groups of MPI ranks "
                                   "read different meshes from") !=
                      std::string::npos),
                  comm),
                Utilities::MPI::n_mpi_processes(comm));
  }
} // namespace

SOFTFACE_TEST(mpi_run_without_cells)
{
  const MPI_Comm     comm    = MPI_COMM_WORLD;
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
  const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
  const bool         rank_0  = rank == 0;
  deallog << "ranks: " << n_ranks << std::endl;

  // Each rank names its own output folder (only rank 0's is made); the
  // number of ranks is in the names, since ctest may run both at once.
  const std::string stem =
    "mpi_run_without_cells_" + std::to_string(n_ranks) + "_";
  const std::string name   = stem + std::to_string(rank);
  const std::string folder = name + "_output";
  const std::string file =
    rank_scene(comm,
               "mpi_run_without_cells.prm",
               name,
               folder,
               "subsection Scene\n  set Mesh file = " +
                 source_file("data/cube30k/mesh.msh") +
                 "\nend\nsubsection Output\n  set Evaluation points = " +
                 source_file("data/points/run_evaluation_points.csv") +
                 "\nend\n");

  std::ostringstream log, errors;
  Simulator          simulator;
  const int          rc = simulator.run(file, log, errors);
  check_equal("largest exit code over the ranks",
              Utilities::MPI::max(rc, comm),
              0);

  // Only the groups' roots hold the cells.
  const Scene &scene = simulator.scene();
  check_equal("ranks that hold the scene's cells",
              Utilities::MPI::sum(int(scene.has_cells()), comm),
              (n_ranks + 1) / 2);
  check_equal("ranks whose cells are not as their place in the group says",
              Utilities::MPI::sum(int(scene.has_cells() != (rank % 2 == 0)),
                                  comm),
              0);
  check_equal("ranks with triangulation cells but no cells said",
              Utilities::MPI::sum(int(!scene.has_cells() &&
                                      scene.triangulation.n_cells() > 0),
                                  comm),
              0);

  check_equal("rank 0 says the members hold no cells",
              !rank_0 || log.str().find(
                           "MPI ranks: " + std::to_string(n_ranks) +
                           " in groups of 2; the groups' members hold "
                           "none of the scene's cells") != std::string::npos,
              true);

  // Every rank's scene tells what rank 0's does.
  check_equal("cells (rank 0)", scene.n_cells(), 30639);
  check_equal(
    "ranks unlike rank 0: counts",
    ranks_unlike_rank_0(std::vector<double>{double(scene.n_cells()),
                                            double(scene.n_dofs()),
                                            double(scene.n_vertices()),
                                            double(scene.n_free_dofs()),
                                            double(scene.n_join_vertices(0)),
                                            double(scene.n_join_vertices(1))},
                        comm),
    0);
  std::vector<double> vertices;
  for (const auto &x : scene.vertices())
    vertices.insert(vertices.end(), {x[0], x[1], x[2]});
  check_equal("ranks unlike rank 0: vertices",
              ranks_unlike_rank_0(vertices, comm),
              0);
  std::vector<types::global_dof_index> vertex_dofs;
  for (const auto &dofs : scene.vertex_dofs())
    vertex_dofs.insert(vertex_dofs.end(), dofs.begin(), dofs.end());
  check_equal("ranks unlike rank 0: vertex DoFs",
              ranks_unlike_rank_0(vertex_dofs, comm),
              0);
  check_equal("ranks unlike rank 0: vertex segments",
              ranks_unlike_rank_0(scene.vertex_segment(), comm),
              0);
  check_equal("ranks unlike rank 0: join DoFs",
              ranks_unlike_rank_0(std::vector<int>(scene.join_dofs().begin(),
                                                   scene.join_dofs().end()),
                                  comm),
              0);
  std::vector<double> centroids;
  for (const auto &segment : scene.segments)
    centroids.insert(centroids.end(),
                     segment.join_centroid.begin(),
                     segment.join_centroid.end());
  check_equal("ranks unlike rank 0: segments' join centroids",
              ranks_unlike_rank_0(centroids, comm),
              0);
  check_equal("ranks unlike rank 0: effects",
              ranks_unlike_rank_0(scene.effects.names, comm),
              0);
  check_equal(
    "ranks unlike rank 0: mesh description",
    ranks_unlike_rank_0(std::vector<std::string>{scene.mesh_description}, comm),
    0);
  check_equal("ranks unlike rank 0: shared join points, active-set limit",
              ranks_unlike_rank_0(
                std::vector<unsigned int>{
                  scene.n_shared_join_points,
                  (unsigned int)scene.resolve_shared_join_points,
                  scene.effects.active_set_limit(),
                  (unsigned int)scene.effects.vertex_constraints.size(),
                  (unsigned int)scene.dofs_are_point_blocks()},
                comm),
              0);
  // The effects' rules, which each rank's effects declare: applied to a
  // tetrahedron of each material id of the mesh and one it lacks (3), they
  // give every rank rank 0's tissues and body forces.
  std::vector<double> rules;
  for (unsigned int t = 0; t < scene.n_tissues(); ++t)
    rules.insert(rules.end(),
                 {scene.tissue(t).youngs_modulus_pa,
                  scene.tissue(t).poissons_ratio});
  Triangulation<3> probe;
  GridGenerator::reference_cell(probe, ReferenceCells::Tetrahedron);
  const auto probe_cell = probe.begin_active();
  for (const types::material_id id : {1, 2, 3})
    {
      probe_cell->set_material_id(id);
      if (id != 3)
        rules.push_back(scene.effects.tissue(probe_cell));
      const Tensor<1, 3> load =
        scene.effects.body_force_vertex_load(probe_cell);
      rules.insert(rules.end(), {load[0], load[1], load[2]});
    }
  check_equal("ranks unlike rank 0: tissues and the effects' rules",
              ranks_unlike_rank_0(rules, comm),
              0);
  // Two tissues, two ids' tissues and three ids' loads: the comparison
  // compared something.
  check_above("tissues and rules compared (rank 0)", rules.size(), 12);
  check_equal("effects (rank 0)", scene.effects.names.size(), 2);
  check_equal(
    "ranks unlike rank 0: body force",
    ranks_unlike_rank_0(std::vector<double>(scene.effects.body_force.begin(),
                                            scene.effects.body_force.end()),
                        comm),
    0);
  check_above("body force (rank 0, N)", scene.effects.body_force.l1_norm(), 1.);

  // Linear FEM on the ranks, each plan combined from its response basis,
  // and nonlinear FEM by Newton: the serial models' answers (to CG's and
  // Newton's tolerances), on every rank alike. Runs model by model, plan by
  // plan.
  const auto &runs = simulator.runs();
  check_equal("model runs (two models, two plans)", runs.size(), 4);
  for (unsigned int r = 0; r < runs.size() && r < 4; ++r)
    {
      const unsigned int p      = r % 2;
      const bool         linear = r < 2;
      const std::string  what   = std::string(linear ? "linear" : "nonlinear") +
                               " fem, plan " + std::to_string(p + 1) + ": ";
      check_equal(what + "ran on the ranks",
                  ran_on_the_ranks(runs[r], n_ranks),
                  true);
      check_equal(what + "combined from the response basis",
                  runs[r].basis_time > 0.,
                  linear);
      const Vector<double> prescribed =
        simulator.plannings().plans[p].planning.prescribed_displacement(scene);
      check_equal(what + "ranks unlike rank 0: prescribed displacement",
                  ranks_unlike_rank_0(std::vector<double>(prescribed.begin(),
                                                          prescribed.end()),
                                      comm),
                  0);
      check_equal(
        what + "ranks unlike rank 0: answer",
        ranks_unlike_rank_0(std::vector<double>(runs[r].displacement.begin(),
                                                runs[r].displacement.end()),
                            comm),
        0);
      if (rank_0)
        {
          check_below(
            what + "relative difference to the serial model",
            relative_difference(runs[r].displacement,
                                linear ? serial_linear_fem(scene, prescribed) :
                                         serial_answer("nonlinear fem",
                                                       simulator.parameters(),
                                                       scene,
                                                       prescribed)),
            1e-8);
          check_above(what + "largest |u_i| (mm)",
                      runs[r].displacement.linfty_norm(),
                      2.9);
        }
    }

  MPI_Barrier(comm);
  if (rank_0)
    {
      check_equal("evaluation_linear_fem_back.csv written",
                  std::filesystem::exists(folder +
                                          "/evaluation_linear_fem_back.csv"),
                  true);
      check_fields_against_serial(folder,
                                  scene,
                                  runs,
                                  n_ranks,
                                  {"displacement_linear_fem_planning",
                                   "displacement_linear_fem_back",
                                   "displacement_nonlinear_fem_planning",
                                   "displacement_nonlinear_fem_back",
                                   "join_point",
                                   "segment_id"});
    }
  check_reference_without_cells(stem, comm);
  check_point_models_without_cells(stem, comm);
  if (n_ranks >= 3)
    check_roots_with_different_meshes(stem, comm);
}

// A scene file run by the simulator on several MPI ranks, by
// ctest on 2 and 3 ranks (mpi_run_scene.mpirun=N.output): every rank ends
// with exit code 0 and the serial models' answers (linear FEM distributed:
// equal to the serial model to 1e-8 relative; the mass tensor model
// distributed too: equal to a serial run), the groups' members (groups of
// two) holding none of the scene's cells; both
// say they ran on the ranks; rank 0 alone writes (each rank names its own
// output folder, only rank 0's exists), but for the fields: a piece
// solution.N.vtu per rank and the record solution.pvtu, which softface's
// mesh reader reads back as the mesh of a serial solution.vtu, with the same
// point data at every point (each model's displacement, the join points and
// segments); the same with the mass tensor model alone, which makes no
// distributed layout (the pieces are then ranges of the scene's cells).
// (A patient scene on the ranks: mpi_run_patient.)

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/planning_list.h>
#include <softface/io/mesh_reader.h>
#include <softface/io/vtu_reader.h>
#include <softface/models/interface.h>
#include <softface/models/linear_fem.h>
#include <softface/outputs/solution.h>
#include <softface/simulator/simulator.h>

#include "mpi_runs.h"
#include "scenes.h"
#include "tests.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

using namespace softface_tests;

SOFTFACE_TEST(mpi_run_scene)
{
  const MPI_Comm     comm    = MPI_COMM_WORLD;
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
  const bool         rank_0  = Utilities::MPI::this_mpi_process(comm) == 0;
  deallog << "ranks: " << n_ranks << std::endl;

  // Each rank names its own output folder (the same scene otherwise), so
  // that what each writes can be told apart; the number of ranks is in the
  // names too: ctest may run the 2- and 3-rank tests at once.
  const unsigned int rank   = Utilities::MPI::this_mpi_process(comm);
  const std::string  stem   = "mpi_run_scene_" + std::to_string(n_ranks) + "_";
  const std::string  name   = stem + std::to_string(rank);
  const std::string  folder = name + "_output";
  const std::string  file = rank_scene(comm, "mpi_run_scene.prm", name, folder);

  std::ostringstream log, errors;
  Simulator          simulator;
  const int          rc = simulator.run(file, log, errors);
  check_equal("largest exit code over the ranks",
              Utilities::MPI::max(rc, comm),
              0);
  check_equal("ranks that printed the table",
              Utilities::MPI::sum(
                int(log.str().find("linear fem") != std::string::npos), comm),
              1);

  const Scene &scene = simulator.scene();
  const auto  &runs  = simulator.runs();
  check_equal("model runs", runs.size(), 2);

  // Both models read nothing of the scene's cells on the ranks: the
  // groups' members hold none (the roots: ranks 0 and 2).
  check_equal("ranks that hold the scene's cells",
              Utilities::MPI::sum(int(scene.has_cells()), comm),
              (n_ranks + 1) / 2);
  for (unsigned int r = 0; r < runs.size() && r < 2; ++r)
    check_equal(
      runs[r].model + ": ranks whose answer is unlike rank 0's",
      ranks_unlike_rank_0(std::vector<double>(runs[r].displacement.begin(),
                                              runs[r].displacement.end()),
                          comm),
      0);

  // Linear FEM: distributed, and its answer the serial model's on rank 0's
  // scene.
  check_equal("linear fem ran on every rank",
              Utilities::MPI::sum(int(!runs[0].failed), comm),
              n_ranks);
  check_equal("linear fem says it ran on the ranks",
              ran_on_the_ranks(runs[0], n_ranks),
              true);
  check_equal("mass tensor says it ran on the ranks",
              ran_on_the_ranks(runs[1], n_ranks),
              true);
  if (rank_0)
    {
      const Vector<double> prescribed =
        simulator.plannings().plans[0].planning.prescribed_displacement(scene);
      check_below("linear fem: relative difference to the serial model",
                  relative_difference(runs[0].displacement,
                                      serial_linear_fem(scene, prescribed)),
                  1e-8);
      check_above("linear fem: largest |u_i| (mm)",
                  runs[0].displacement.linfty_norm(),
                  5.9);

      // The mass tensor model, distributed: the ranks sweep in the serial
      // order, so the answer is the serial one.
      check_equal("mass tensor: largest difference to a serial run (mm)",
                  largest_difference(runs[1].displacement,
                                     serial_answer("mass tensor",
                                                   simulator.parameters(),
                                                   scene,
                                                   prescribed)),
                  0.);
    }

  // Rank 0 alone wrote its outputs: the summary has a row per model, and
  // the other ranks' folders do not exist.
  MPI_Barrier(comm);
  if (rank_0)
    {
      std::ifstream summary(folder + "/summary.csv");
      std::string   line;
      unsigned int  rows = 0;
      while (std::getline(summary, line))
        ++rows;
      check_equal("summary.csv rows (header + two models)", rows, 3);
      check_equal("displacements_linear_fem.csv written",
                  std::filesystem::exists(folder +
                                          "/displacements_linear_fem.csv"),
                  true);
      unsigned int others = 0;
      for (unsigned int r = 1; r < n_ranks; ++r)
        others += std::filesystem::exists(stem + std::to_string(r) + "_output");
      check_equal("output folders of the other ranks", others, 0);

      // The fields: a piece per rank and their record, which softface's
      // reader reads back as the mesh of a serial solution.vtu of the same
      // run (Outputs::write_vtu(), as a serial run writes it).
      check_fields_against_serial(folder,
                                  scene,
                                  runs,
                                  n_ranks,
                                  {"displacement_linear_fem",
                                   "displacement_mass_tensor",
                                   "join_point",
                                   "segment_id"});
    }

  // The mass tensor model alone, every rank holding the scene (groups of
  // one), makes no distributed layout (its ranks share its own blocks): the
  // pieces are then ranges of the scene's cells (Outputs::write_pvtu() from
  // the scene), with the same fields.
  const std::string alone = name + "_mass_tensor_alone";
  const std::string alone_file =
    rank_scene(comm,
               "mpi_run_scene.prm",
               alone,
               alone,
               "subsection Models\n  set Models = mass tensor\n  set Mesh "
               "group size = 1\nend\n");
  std::ostringstream alone_log, alone_errors;
  Simulator          alone_simulator;
  check_equal("mass tensor alone: largest exit code over the ranks",
              Utilities::MPI::max(
                alone_simulator.run(alone_file, alone_log, alone_errors), comm),
              0);
  MPI_Barrier(comm);
  if (rank_0)
    check_fields_against_serial(alone,
                                alone_simulator.scene(),
                                alone_simulator.runs(),
                                n_ranks,
                                {"displacement_mass_tensor",
                                 "join_point",
                                 "segment_id"});
}

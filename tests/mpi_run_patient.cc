// A patient scene on several MPI ranks, by ctest on 2 ranks
// (mpi_run_patient.mpirun=2.output; Mesh_3 on rank 0 beside a third rank
// that waits would oversubscribe this machine's two cores): rank 0 alone
// runs the pipeline (tests/mpi_run_patient.prm, the phantom of
// run_patient.prm), which writes its stages, and every rank reads the mesh
// it made, so the ranks hold the same mesh (same cells, vertices and
// coordinates on every rank; Mesh_3 does not make the same mesh twice).
// On that mesh linear FEM on the ranks equals the serial model to 1e-8
// relative, the mass tensor model equals its serial run to the last bit,
// and nonlinear FEM runs on the ranks too. Rank 0 alone maps and writes the
// skins (skin.csv, a skin per model) and the patient's figures; the other
// ranks have no skin output. A truth scene as the post-operative skin is
// refused on every rank, before any work. Last, linear and nonlinear FEM in
// a group of two ranks: rank 0 alone runs the pipeline and holds the mesh,
// rank 1 none of its cells, and the answers are the serial models' on rank
// 0's scene.

#include <deal.II/base/mpi.h>

#include <softface/core/planning_list.h>
#include <softface/simulator/simulator.h>

#include "mpi_runs.h"
#include "scenes.h"
#include "tests.h"

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace softface_tests;

namespace
{
  // The patient with the models that read only their part of the mesh
  // (Models/Mesh group size = 2).
  void
  check_in_a_group(const MPI_Comm comm)
  {
    const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const std::string  folder  = "output/mpi_run_patient_group";
    const std::string  prm     = "mpi_run_patient_group.prm";
    if (rank == 0)
      {
        std::filesystem::remove_all(folder);
        std::ofstream out(prm);
        out << "include " << source_file("mpi_run_patient.prm") << '\n'
            << "subsection Models\n  set Models = linear fem, nonlinear fem\n"
            << "  set Mesh group size = 2\nend\n"
            << "subsection Output\n  set Output directory = " << folder
            << "\nend\n";
      }
    MPI_Barrier(comm);
    std::ostringstream log, errors;
    Simulator          simulator;
    const int          rc = simulator.run(prm, log, errors);
    deallog << "in a group of two, linear and nonlinear FEM:" << std::endl;
    check_equal("  largest exit code over the ranks",
                Utilities::MPI::max(rc, comm),
                0);
    const Scene &scene = simulator.scene();
    check_equal("  ranks that hold the scene's cells",
                Utilities::MPI::sum(int(scene.has_cells()), comm),
                (n_ranks + 1) / 2);
    check_equal("  rank 0 says the member holds none",
                rank != 0 ||
                  log.str().find("the groups' members hold none "
                                 "of the scene's cells") != std::string::npos,
                true);
    const auto &runs = simulator.runs();
    check_equal("  model runs", runs.size(), 2);
    for (const auto &run : runs)
      {
        check_equal("  " + run.label() + " ran on the ranks",
                    !run.failed && ran_on_the_ranks(run, n_ranks),
                    true);
        const std::vector<double> answer(run.displacement.begin(),
                                         run.displacement.end());
        check_equal("  " + run.label() + ": ranks unlike rank 0",
                    Utilities::MPI::sum(
                      int(answer != Utilities::MPI::broadcast(comm, answer)),
                      comm),
                    0);
      }
    if (rank == 0 && runs.size() == 2)
      {
        const Vector<double> prescribed =
          simulator.plannings().plans[0].planning.prescribed_displacement(
            scene);
        check_below("  linear fem: relative difference to the serial model",
                    relative_difference(runs[0].displacement,
                                        serial_linear_fem(scene, prescribed)),
                    1e-8);
        check_below("  nonlinear fem: relative difference to the serial model",
                    relative_difference(runs[1].displacement,
                                        serial_answer("nonlinear fem",
                                                      simulator.parameters(),
                                                      scene,
                                                      prescribed)),
                    1e-8);
        for (const std::string file :
             {"skin_linear_fem.ply", "skin_nonlinear_fem.ply", "solution.pvtu"})
          check_equal("  " + file + " written",
                      std::filesystem::exists(folder + "/" + file),
                      true);
        std::filesystem::remove(prm);
      }
  }
} // namespace

SOFTFACE_TEST(mpi_run_patient)
{
  const MPI_Comm     comm    = MPI_COMM_WORLD;
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
  const bool         rank_0  = Utilities::MPI::this_mpi_process(comm) == 0;
  deallog << "ranks: " << n_ranks << std::endl;
  if (rank_0)
    std::filesystem::remove_all("output/mpi_run_patient");
  MPI_Barrier(comm);

  std::ostringstream log, errors;
  Simulator          simulator;
  const int rc = simulator.run(source_file("mpi_run_patient.prm"), log, errors);
  check_equal("largest exit code over the ranks",
              Utilities::MPI::max(rc, comm),
              0);

  // The same mesh on every rank.
  const Scene &scene   = simulator.scene();
  double       sum_xyz = 0.;
  for (const auto &vertex : scene.triangulation.get_vertices())
    sum_xyz += vertex[0] + 2. * vertex[1] + 3. * vertex[2];
  const auto same = [&](const std::string &what, const double value) {
    check_equal(what + ": ranks that differ from rank 0",
                Utilities::MPI::sum(
                  int(value != Utilities::MPI::broadcast(comm, value, 0)),
                  comm),
                0);
  };
  check_within(
    "tetrahedra", scene.triangulation.n_active_cells(), 4000, 16000, 9);
  same("tetrahedra", scene.triangulation.n_active_cells());
  same("vertices", scene.n_vertices());
  same("sum of x + 2y + 3z over the vertices", sum_xyz);
  for (unsigned int s = 0; s < scene.segments.size(); ++s)
    same(scene.segments[s].name + ": join points", scene.n_join_vertices(s));

  const auto &runs = simulator.runs();
  check_equal("model runs", runs.size(), 3);
  for (const auto &run : runs)
    {
      check_equal(run.label() + " failed", run.failed, false);
      check_equal(run.label() + " says it ran on the ranks",
                  ran_on_the_ranks(run, n_ranks),
                  true);
    }

  // Serial runs of the same models on the same scene; the join points where
  // the plan puts them.
  const Vector<double> prescribed =
    simulator.plannings().plans[0].planning.prescribed_displacement(scene);
  check_below("linear fem: relative difference to the serial model",
              relative_difference(runs[0].displacement,
                                  serial_linear_fem(scene, prescribed)),
              1e-8);
  double join_error = 0.;
  for (types::global_dof_index i = 0; i < prescribed.size(); ++i)
    if (scene.join_dofs()[i])
      join_error =
        std::max(join_error, std::abs(runs[0].displacement[i] - prescribed[i]));
  check_below("linear fem: join points, max |u_i - planned| (mm)",
              join_error,
              1e-9);
  check_equal("mass tensor: largest difference to a serial run (mm)",
              largest_difference(runs[1].displacement,
                                 serial_answer("mass tensor",
                                               simulator.parameters(),
                                               scene,
                                               prescribed)),
              0.);

  // Rank 0 wrote the patient's figures and the skins.
  MPI_Barrier(comm);
  if (rank_0)
    for (const std::string file : {"patient.csv",
                                   "skin.csv",
                                   "skin_linear_fem.ply",
                                   "skin_mass_tensor.vtp",
                                   "skin_nonlinear_fem.ply",
                                   "solution.pvtu"})
      check_equal(file + " written",
                  std::filesystem::exists("output/mpi_run_patient/" + file),
                  true);

  // Rank 0 alone mapped the skins.
  check_equal("ranks with a skin output",
              Utilities::MPI::sum(int(simulator.skin() != nullptr), comm),
              1);
  check_equal("rank 0 has it", simulator.skin() != nullptr, rank_0);

  // A truth scene would run as a scene of its own while rank 0 writes its
  // files: refused before any work, on every rank alike.
  int               refused   = 0;
  const std::string truth_prm = "mpi_run_patient_truth.prm";
  if (rank_0)
    {
      std::ofstream prm(truth_prm);
      prm << "include " << source_file("mpi_run_patient.prm") << '\n'
          << "subsection Skin\n  set Post-operative skin = truth.prm\nend\n";
    }
  MPI_Barrier(comm);
  try
    {
      Simulator          truth;
      std::ostringstream quiet;
      truth.run(truth_prm, quiet, quiet);
    }
  catch (const Error &e)
    {
      const std::string message = e.what();
      refused = message.find("truth scene") != std::string::npos &&
                message.find("one MPI rank only") != std::string::npos;
      if (rank_0)
        deallog << "truth scene: " << message.substr(message.find("Skin/"))
                << std::endl;
    }
  check_equal("ranks that refused the truth scene",
              Utilities::MPI::sum(refused, comm),
              int(n_ranks));
  MPI_Barrier(comm);
  if (rank_0)
    std::filesystem::remove(truth_prm);

  check_in_a_group(comm);
}

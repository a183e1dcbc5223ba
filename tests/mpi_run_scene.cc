// A scene file run by the simulator on several MPI ranks (issue 20), by
// ctest on 2 and 3 ranks (mpi_run_scene.mpirun=N.output): every rank ends
// with exit code 0 and the serial models' answers (linear FEM distributed:
// equal to the serial model to 1e-8 relative; the mass tensor model
// distributed too: equal to a serial run); both
// say they ran on the ranks; rank 0 alone writes (each rank names its own
// output folder, only rank 0's exists), but for the fields: a piece
// solution.N.vtu per rank and the record solution.pvtu, which softface's
// mesh reader reads back as the mesh of a serial solution.vtu, with the same
// point data at every point (each model's displacement, the join points and
// segments). (A patient scene on the ranks: mpi_run_patient.)

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/planning_list.h>
#include <softface/io/mesh_reader.h>
#include <softface/io/vtu_reader.h>
#include <softface/models/interface.h>
#include <softface/models/linear_fem.h>
#include <softface/simulator/output.h>
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
  std::filesystem::remove_all(folder);
  {
    std::ifstream in(source_file("mpi_run_scene.prm"));
    std::ofstream out(name + ".prm");
    out << in.rdbuf()
        << "subsection Output\n  set Output directory = " << folder
        << "\nend\n";
  }
  MPI_Barrier(comm);

  std::ostringstream log, errors;
  Simulator          simulator;
  const int          rc = simulator.run(name + ".prm", log, errors);
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

  const Vector<double> prescribed =
    simulator.plannings().plans[0].planning.prescribed_displacement(scene);

  // Linear FEM: distributed, and its answer the serial model's.
  check_equal("linear fem ran on every rank", runs[0].failed, false);
  check_equal("linear fem says it ran on the ranks",
              ran_on_the_ranks(runs[0], n_ranks),
              true);
  check_below("linear fem: relative difference to the serial model",
              relative_difference(runs[0].displacement,
                                  serial_linear_fem(scene, prescribed)),
              1e-8);
  check_above("linear fem: largest |u_i| (mm)",
              runs[0].displacement.linfty_norm(),
              5.9);

  // The mass tensor model, distributed: the ranks sweep in the serial
  // order, so the answer is the serial one.
  check_equal("mass tensor says it ran on the ranks",
              ran_on_the_ranks(runs[1], n_ranks),
              true);
  check_equal("mass tensor: largest difference to a serial run (mm)",
              largest_difference(runs[1].displacement,
                                 serial_answer("mass tensor",
                                               simulator.parameters(),
                                               scene,
                                               prescribed)),
              0.);

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
      // run (Output::write_vtu(), as a serial run writes it).
      unsigned int pieces = 0;
      while (std::filesystem::exists(folder + "/solution." +
                                     std::to_string(pieces) + ".vtu"))
        ++pieces;
      check_equal("solution.N.vtu pieces", pieces, n_ranks);
      check_equal("solution.vtu written (on several ranks: no)",
                  std::filesystem::exists(folder + "/solution.vtu"),
                  false);
      Output::write_vtu(scene, runs, folder + "/serial.vtu");
      Triangulation<3> record, serial_file;
      Mesh::read_file(folder + "/solution.pvtu", record);
      Mesh::read_file(folder + "/serial.vtu", serial_file);
      check_equal("cells, solution.pvtu against serial.vtu",
                  record.n_active_cells(),
                  serial_file.n_active_cells());
      // DataOut writes each cell's own copy of its vertices; the reader
      // merges copies across pieces only. So the distinct positions count.
      const auto positions = [](const Triangulation<3> &mesh) {
        std::vector<std::array<double, 3>> list;
        for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
          if (mesh.get_used_vertices()[v])
            list.push_back({{mesh.get_vertices()[v][0],
                             mesh.get_vertices()[v][1],
                             mesh.get_vertices()[v][2]}});
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        return list;
      };
      const auto record_points = positions(record);
      check_equal("distinct vertex positions, solution.pvtu against serial.vtu",
                  record_points == positions(serial_file),
                  true);
      check_equal("distinct vertex positions, solution.pvtu against the scene",
                  record_points.size(),
                  scene.n_vertices());
      check_equal("cells, solution.pvtu against the scene",
                  record.n_active_cells(),
                  scene.triangulation.n_active_cells());
      // The cells in any order (the reader orders them for locality): their
      // centres, sorted.
      const auto centres = [](const Triangulation<3> &mesh) {
        std::vector<std::array<double, 3>> list;
        for (const auto &cell : mesh.active_cell_iterators())
          {
            const Point<3> c = cell->center();
            list.push_back({{c[0], c[1], c[2]}});
          }
        std::sort(list.begin(), list.end());
        return list;
      };
      const auto a = centres(record), b = centres(serial_file);
      double     largest = 0.;
      for (unsigned int i = 0; i < a.size() && i < b.size(); ++i)
        for (unsigned int d = 0; d < 3; ++d)
          largest = std::max(largest, std::abs(a[i][d] - b[i][d]));
      check_below("largest difference of a cell centre (mm)", largest, 1e-12);

      // The point data: at every point the record holds, each array's
      // values equal the serial file's at the same position (both files
      // repeat a vertex per cell, with the same values).
      for (const std::string array : {"displacement_linear_fem",
                                      "displacement_mass_tensor",
                                      "join_point",
                                      "segment_id"})
        {
          const Mesh::PointField in_record =
            Mesh::read_vtu_point_field(folder + "/solution.pvtu", array);
          const Mesh::PointField in_serial =
            Mesh::read_vtu_point_field(folder + "/serial.vtu", array);
          const unsigned int n = in_serial.n_components;
          std::map<std::array<double, 3>, std::vector<double>> at;
          for (std::size_t i = 0; i < in_serial.points.size(); ++i)
            at[{{in_serial.points[i][0],
                 in_serial.points[i][1],
                 in_serial.points[i][2]}}]
              .assign(in_serial.values.begin() + n * i,
                      in_serial.values.begin() + n * (i + 1));
          unsigned int unmatched  = 0;
          double       difference = 0., size = 0.;
          for (std::size_t i = 0; i < in_record.points.size(); ++i)
            {
              const auto found = at.find({{in_record.points[i][0],
                                           in_record.points[i][1],
                                           in_record.points[i][2]}});
              if (found == at.end() || in_record.n_components != n)
                {
                  ++unmatched;
                  continue;
                }
              for (unsigned int c = 0; c < n; ++c)
                {
                  const double value = in_record.values[n * i + c];
                  difference =
                    std::max(difference, std::abs(value - found->second[c]));
                  size = std::max(size, std::abs(value));
                }
            }
          // Each file repeats a vertex once per cell, and each cell is in
          // one piece: as many points in all pieces as in the serial file.
          check_equal(array + ": points of solution.pvtu against serial.vtu",
                      in_record.points.size(),
                      in_serial.points.size());
          check_equal(array + ": points of solution.pvtu not in serial.vtu",
                      unmatched,
                      0);
          check_equal(array + ": largest difference to serial.vtu",
                      difference,
                      0.);
          // Not a field of zeros: the comparison compared something.
          check_above(array + ": largest value", size, 0.99);
        }
    }
}

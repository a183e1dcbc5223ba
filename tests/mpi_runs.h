#ifndef softface_tests_mpi_runs_h
#define softface_tests_mpi_runs_h

// What the simulator's tests on several MPI ranks compare a run with: its
// models' own word that they ran on the ranks, and the same models run
// serially (MPI_COMM_SELF) on the same scene in the same process.

#include <softface/core/scene.h>
#include <softface/io/mesh_reader.h>
#include <softface/io/vtu_reader.h>
#include <softface/models/interface.h>
#include <softface/models/linear_fem.h>
#include <softface/outputs/report.h>
#include <softface/outputs/solution.h>

#include "tests.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace softface_tests
{
  using namespace softface;

  /**
   * This rank's copy <name>.prm of the tests' scene @p prm with @p settings
   * appended and its own output folder @p folder (emptied first), so that
   * what each rank writes can be told apart. Every rank's is written before
   * any rank runs it. Collective; returns the file's name.
   */
  inline std::string
  rank_scene(const MPI_Comm     comm,
             const std::string &prm,
             const std::string &name,
             const std::string &folder,
             const std::string &settings = "")
  {
    std::filesystem::remove_all(folder);
    {
      std::ifstream in(source_file(prm));
      std::ofstream out(name + ".prm");
      out << in.rdbuf() << settings
          << "subsection Output\n  set Output directory = " << folder
          << "\nend\n";
    }
    MPI_Barrier(comm);
    return name + ".prm";
  }

  /// On how many ranks @p values differ from rank 0's (exactly).
  /// Collective.
  template <typename T>
  int
  ranks_unlike_rank_0(const std::vector<T> &values, const MPI_Comm comm)
  {
    return Utilities::MPI::sum(int(values !=
                                   Utilities::MPI::broadcast(comm, values, 0)),
                               comm);
  }

  /// Does @p run say (its "MPI ranks" figure) that it ran on @p n_ranks?
  inline bool
  ran_on_the_ranks(const Report::ModelRun &run, const unsigned int n_ranks)
  {
    bool distributed = false;
    for (const auto &detail : run.statistics.details)
      distributed |= detail.name == "MPI ranks" && detail.value == n_ranks;
    return distributed;
  }

  /// The serial linear FEM answer, CG to 1e-12.
  inline Vector<double>
  serial_linear_fem(const Scene &scene, const Vector<double> &prescribed)
  {
    Models::LinearFEM model;
    model.set_solver("cg amg", 1e-12);
    model.setup(scene, {nullptr, MPI_COMM_SELF, nullptr});
    Vector<double> u;
    model.solve(prescribed, u);
    return u;
  }

  /// Model @p name with the run's parameters @p prm, on one rank.
  inline Vector<double>
  serial_answer(const std::string    &name,
                ParameterHandler     &prm,
                const Scene          &scene,
                const Vector<double> &prescribed)
  {
    auto model = Models::create(name, prm);
    model->setup(scene, {nullptr, MPI_COMM_SELF, nullptr});
    Vector<double> u;
    model->solve(prescribed, u);
    return u;
  }

  /// The largest |a_i - b_i|.
  inline double
  largest_difference(const Vector<double> &a, const Vector<double> &b)
  {
    Vector<double> difference = a;
    difference -= b;
    return difference.linfty_norm();
  }

  /**
   * The fields a run on @p n_ranks ranks wrote in @p folder (rank 0 calls
   * this): a piece solution.N.vtu per rank and their record solution.pvtu,
   * which softface's reader reads back as the mesh of a serial
   * solution.vtu of the same run (Outputs::write_vtu(), as a serial run
   * writes it), with the same material ids and the same values of each of
   * @p arrays at every point.
   */
  inline void
  check_fields_against_serial(const std::string                   &folder,
                              const Scene                         &scene,
                              const std::vector<Report::ModelRun> &runs,
                              const unsigned int                   n_ranks,
                              const std::vector<std::string>      &arrays)
  {
    unsigned int pieces = 0;
    while (std::filesystem::exists(folder + "/solution." +
                                   std::to_string(pieces) + ".vtu"))
      ++pieces;
    check_equal("solution.N.vtu pieces", pieces, n_ranks);
    check_equal("solution.vtu written (on several ranks: no)",
                std::filesystem::exists(folder + "/solution.vtu"),
                false);
    Outputs::write_vtu(scene, runs, folder + "/serial.vtu");
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
    // centres, sorted, with their material ids.
    const auto centres = [](const Triangulation<3> &mesh) {
      std::vector<std::array<double, 4>> list;
      for (const auto &cell : mesh.active_cell_iterators())
        {
          const Point<3> c = cell->center();
          list.push_back({{c[0], c[1], c[2], double(cell->material_id())}});
        }
      std::sort(list.begin(), list.end());
      return list;
    };
    const auto   a = centres(record), b = centres(serial_file);
    double       largest        = 0.;
    unsigned int other_material = 0;
    for (unsigned int i = 0; i < a.size() && i < b.size(); ++i)
      {
        for (unsigned int d = 0; d < 3; ++d)
          largest = std::max(largest, std::abs(a[i][d] - b[i][d]));
        other_material += a[i][3] != b[i][3];
      }
    check_below("largest difference of a cell centre (mm)", largest, 1e-12);
    check_equal("cells whose material id differs from serial.vtu's",
                other_material,
                0);

    // The point data: at every point the record holds, each array's
    // values equal the serial file's at the same position (both files
    // repeat a vertex per cell, with the same values).
    for (const std::string &array : arrays)
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
} // namespace softface_tests

#endif

// 'Output/Evaluation points' through the simulator: every model's
// evaluation_<model>.csv has one row per point of the file, in its order; at
// a mesh vertex it holds the model's nodal displacement (displacements_
// <model>.csv), and linear FEM's value at the centre of a grid box, which
// lies on the main diagonal that the box's six tetrahedra share, is the P1
// interpolation along it: the mean of the diagonal's two end vertices.

#include <deal.II/base/utilities.h>

#include "run_scene.h"

#include <fstream>

namespace
{
  using namespace dealii;

  std::vector<std::vector<double>>
  read_rows(const std::string &filename)
  {
    std::ifstream                    in(filename);
    std::vector<std::vector<double>> rows;
    std::string                      line;
    std::getline(in, line);
    while (std::getline(in, line))
      rows.push_back(
        Utilities::string_to_double(Utilities::split_string_list(line)));
    return rows;
  }

  // The displacement of the vertex nearest to x in a nodal CSV.
  Tensor<1, 3>
  nodal_at(const std::vector<std::vector<double>> &nodal, const Point<3> &x)
  {
    const std::vector<double> *best     = nullptr;
    double                     distance = 1e300;
    for (const auto &row : nodal)
      {
        const double d = x.distance(Point<3>(row[0], row[1], row[2]));
        if (d < distance)
          distance = d, best = &row;
      }
    AssertThrow(distance < 1e-8, ExcMessage("no vertex there"));
    return Tensor<1, 3>({(*best)[3], (*best)[4], (*best)[5]});
  }
} // namespace

SOFTFACE_TEST(run_evaluation_points)
{
  softface::Simulator simulator;
  const int           exit_code = softface_tests::run_scene(
    simulator, softface_tests::source_file("run_evaluation_points.prm"));
  softface_tests::check_equal("exit code", exit_code, 0);

  const std::string out = "run_evaluation_points_output/";
  for (const std::string model : {"linear_fem", "reference_fem"})
    {
      const auto rows  = read_rows(out + "evaluation_" + model + ".csv");
      const auto nodal = read_rows(out + "displacements_" + model + ".csv");
      softface_tests::check_equal(model + ": evaluated points", rows.size(), 4);
      std::vector<Point<3>>     x;
      std::vector<Tensor<1, 3>> u;
      for (const auto &row : rows)
        {
          x.emplace_back(row[0], row[1], row[2]);
          u.push_back(Tensor<1, 3>({row[3], row[4], row[5]}));
          deallog << model << " at (" << softface_tests::rounded(row[0], 6)
                  << ", " << softface_tests::rounded(row[1], 6) << ", "
                  << softface_tests::rounded(row[2], 6)
                  << "): " << softface_tests::rounded(row[3], 5) << ' '
                  << softface_tests::rounded(row[4], 5) << ' '
                  << softface_tests::rounded(row[5], 5) << std::endl;
        }
      const double vertex_error =
        std::max((u[0] - nodal_at(nodal, x[0])).norm(),
                 (u[1] - nodal_at(nodal, x[1])).norm());
      softface_tests::check_below(model +
                                    ": at vertices: max |evaluated - nodal| "
                                    "(mm)",
                                  vertex_error,
                                  1e-8);
      if (model == "linear_fem")
        {
          const Tensor<1, 3> mean =
            0.5 * (nodal_at(nodal, Point<3>(35. / 3, 70. / 3, 35)) +
                   nodal_at(nodal, Point<3>(70. / 3, 35, 45)));
          softface_tests::check_below(
            "linear_fem: at the box centre: |evaluated - mean of the "
            "diagonal's ends| (mm)",
            (u[2] - mean).norm(),
            1e-8);
        }
    }
}

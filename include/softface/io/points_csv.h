#ifndef softface_io_points_csv_h
#define softface_io_points_csv_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Points from a CSV file whose first three columns are x, y, z (a header
   * line is skipped, e.g. the displacements_<model>.csv softface writes).
   * Errors name the file and line.
   */
  std::vector<Point<3>>
  read_points_csv(const std::string &filename);

  /// x,y,z,ux,uy,uz, one row per point.
  void
  write_point_values_csv(const std::vector<Point<3>>     &points,
                         const std::vector<Tensor<1, 3>> &values,
                         const std::string               &filename);
} // namespace softface

#endif

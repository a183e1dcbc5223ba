// Points and point values as CSV (io): reading x,y,z evaluation points and
// writing x,y,z,ux,uy,uz rows.

#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/io/points_csv.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace softface
{
  std::vector<Point<3>>
  read_points_csv(const std::string &filename)
  {
    std::ifstream in(filename);
    if (!in)
      throw Error("Cannot open evaluation points file '" + filename + "'.");
    std::vector<Point<3>> points;
    std::string           line;
    unsigned int          line_number = 0;
    while (std::getline(in, line))
      {
        ++line_number;
        if (line.empty() || line[0] == '#')
          continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream fields(line);
        Point<3>           p;
        if (!(fields >> p[0] >> p[1] >> p[2]))
          {
            if (line_number == 1)
              continue; // header
            throw Error(filename + ":" + std::to_string(line_number) +
                        ": expected three coordinates x,y,z.");
          }
        points.push_back(p);
      }
    if (points.empty())
      throw Error("Evaluation points file '" + filename + "' has no points.");
    return points;
  }

  void
  write_point_values_csv(const std::vector<Point<3>>     &points,
                         const std::vector<Tensor<1, 3>> &values,
                         const std::string               &filename)
  {
    std::ofstream out = open_output_file(filename);
    out << "x,y,z,ux,uy,uz\n" << std::setprecision(12);
    for (unsigned int i = 0; i < points.size(); ++i)
      out << points[i][0] << ',' << points[i][1] << ',' << points[i][2] << ','
          << values[i][0] << ',' << values[i][1] << ',' << values[i][2] << '\n';
  }
} // namespace softface

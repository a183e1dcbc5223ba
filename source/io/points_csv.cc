// Points and point values as CSV (io): reading x,y,z evaluation points and
// writing x,y,z,ux,uy,uz rows.

#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/io/points_csv.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

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
        if (!line.empty() && line.back() == '\r')
          line.pop_back();
        if (line.empty() || line[0] == '#')
          continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream       split(line);
        std::vector<std::string> fields;
        for (std::string field; split >> field;)
          fields.push_back(field);
        // Each field as a number, strictly (strtod on the whole field).
        std::vector<double> values;
        for (const auto &field : fields)
          {
            char        *end   = nullptr;
            const double value = std::strtod(field.c_str(), &end);
            if (end == field.c_str() + field.size())
              values.push_back(value);
          }
        // The first line is a header only if no field is a number: a
        // first point with a typo must not vanish as a "header".
        if (line_number == 1 && values.empty())
          continue;
        const std::string where =
          filename + ":" + std::to_string(line_number) + ": ";
        if (fields.size() != 3 || values.size() != 3)
          throw Error(where + "expected three numbers x,y,z (got '" +
                      line.substr(0, 60) + "').");
        for (const double v : values)
          if (!std::isfinite(v))
            throw Error(where + "a coordinate is not finite.");
        points.emplace_back(values[0], values[1], values[2]);
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

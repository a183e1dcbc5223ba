// Distances between skin surfaces (validation; Mollemans et al. 2007,
// Sec. 3.5.1): signed closest-point distances, masks and the statistics of a
// distance map (mean, variance, maximum, 50/90/95 % percentiles).

#include <boost/algorithm/string.hpp>

#include <softface/core/error.h>
#include <softface/validation/distances.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softface
{
  namespace Validation
  {
    SignedDistance::SignedDistance(const SurfaceMapping::Surface &to)
        : to(to)
        , search(to)
        , normals(SurfaceMapping::point_normals(to))
    {}

    double
    SignedDistance::operator()(const Point<3> &point) const
    {
      const auto   hit = search.closest(point);
      const auto  &tri = to.triangles[hit.triangle];
      Tensor<1, 3> normal;
      for (unsigned int k = 0; k < 3; ++k)
        normal += hit.barycentric[k] * normals[tri[k]];
      const double side = (point - hit.point) * normal;
      return side < 0. ? -hit.distance : hit.distance;
    }

    std::vector<double>
    signed_distances(const std::vector<Point<3>>   &points,
                     const SurfaceMapping::Surface &to)
    {
      const SignedDistance distance(to);
      std::vector<double>  distances(points.size());
      for (unsigned int i = 0; i < points.size(); ++i)
        distances[i] = distance(points[i]);
      return distances;
    }

    Mask
    Mask::parse(const std::string &text, const std::string &parameter)
    {
      Mask                     mask;
      std::vector<std::string> boxes;
      const std::string        trimmed = boost::algorithm::trim_copy(text);
      if (trimmed.empty())
        return mask;
      boost::algorithm::split(boxes, trimmed, boost::algorithm::is_any_of("|"));
      for (const std::string &box : boxes)
        {
          std::vector<std::string> corners;
          boost::algorithm::split(corners,
                                  box,
                                  boost::algorithm::is_any_of(";"));
          std::vector<Point<3>> p;
          for (const std::string &corner : corners)
            {
              std::vector<std::string> values;
              boost::algorithm::split(values,
                                      corner,
                                      boost::algorithm::is_any_of(","));
              Point<3> x;
              bool     good = values.size() == 3;
              for (unsigned int d = 0; good && d < 3; ++d)
                {
                  const std::string v = boost::algorithm::trim_copy(values[d]);
                  char             *end = nullptr;
                  x[d]                  = std::strtod(v.c_str(), &end);
                  good = !v.empty() && *end == '\0' && std::isfinite(x[d]);
                }
              if (!good)
                throw Error(parameter + ": '" + box +
                            "' is not a box 'x0, y0, z0; x1, y1, z1' (mm).");
              p.push_back(x);
            }
          if (p.size() != 2)
            throw Error(parameter + ": '" + box +
                        "' is not a box 'x0, y0, z0; x1, y1, z1' (mm).");
          mask.boxes.emplace_back(p);
        }
      return mask;
    }

    bool
    Mask::masked(const Point<3> &p) const
    {
      for (const auto &box : boxes)
        if (box.point_inside(p))
          return true;
      return false;
    }

    double
    percentile(std::vector<double> values, const double q)
    {
      AssertThrow(!values.empty(), ExcMessage("percentile of nothing"));
      std::sort(values.begin(), values.end());
      const double       position = q / 100. * (values.size() - 1);
      const unsigned int below    = std::floor(position);
      if (below + 1 >= values.size())
        return values.back();
      return values[below] +
             (position - below) * (values[below + 1] - values[below]);
    }

    Statistics
    statistics(const std::vector<double>   &distances,
               const std::vector<Point<3>> &points,
               const Mask                  &mask,
               const std::vector<bool>     &in_region)
    {
      AssertDimension(distances.size(), points.size());
      std::vector<double> kept, absolute;
      for (unsigned int i = 0; i < distances.size(); ++i)
        if (!mask.masked(points[i]) && (in_region.empty() || in_region[i]))
          {
            kept.push_back(distances[i]);
            absolute.push_back(std::abs(distances[i]));
          }
      if (kept.empty())
        throw Error("The mask leaves no point of the skin to measure (" +
                    std::to_string(distances.size()) +
                    " points, all in masked boxes or out of the mesh's "
                    "reach).");
      Statistics s;
      s.n = kept.size();
      for (unsigned int i = 0; i < kept.size(); ++i)
        {
          s.mean += kept[i] / s.n;
          s.mean_absolute += absolute[i] / s.n;
          s.max_absolute = std::max(s.max_absolute, absolute[i]);
        }
      for (const double d : kept)
        s.variance += (d - s.mean) * (d - s.mean) / s.n;
      s.p50 = percentile(absolute, 50.);
      s.p90 = percentile(absolute, 90.);
      s.p95 = percentile(absolute, 95.);
      return s;
    }
  } // namespace Validation
} // namespace softface

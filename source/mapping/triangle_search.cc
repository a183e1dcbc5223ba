// Closest points on triangle surfaces (mapping, validation): the point of a
// triangle closest to a point by its Voronoi regions, an R-tree of triangle
// boxes searched nearest first, point normals and the manifold check that the
// skin surfaces must pass.

#include <deal.II/base/geometry_info.h>

#include <softface/core/error.h>
#include <softface/mapping/triangle_search.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace softface
{
  namespace SurfaceMapping
  {
    std::pair<Point<3>, std::array<double, 3>>
    closest_point_on_triangle(const Point<3>                &p,
                              const std::array<Point<3>, 3> &t)
    {
      // Which of the seven Voronoi regions of the triangle (three vertices,
      // three edges, the face) holds p (Ericson, Real-Time Collision
      // Detection, 5.1.5).
      const Tensor<1, 3> ab = t[1] - t[0], ac = t[2] - t[0], ap = p - t[0];
      const double       d1 = ab * ap, d2 = ac * ap;
      if (d1 <= 0. && d2 <= 0.)
        return {t[0], {{1., 0., 0.}}};
      const Tensor<1, 3> bp = p - t[1];
      const double       d3 = ab * bp, d4 = ac * bp;
      if (d3 >= 0. && d4 <= d3)
        return {t[1], {{0., 1., 0.}}};
      const double vc = d1 * d4 - d3 * d2;
      if (vc <= 0. && d1 >= 0. && d3 <= 0.)
        {
          const double v = d1 / (d1 - d3);
          return {t[0] + v * ab, {{1. - v, v, 0.}}};
        }
      const Tensor<1, 3> cp = p - t[2];
      const double       d5 = ab * cp, d6 = ac * cp;
      if (d6 >= 0. && d5 <= d6)
        return {t[2], {{0., 0., 1.}}};
      const double vb = d5 * d2 - d1 * d6;
      if (vb <= 0. && d2 >= 0. && d6 <= 0.)
        {
          const double w = d2 / (d2 - d6);
          return {t[0] + w * ac, {{1. - w, 0., w}}};
        }
      const double va = d3 * d6 - d5 * d4;
      if (va <= 0. && (d4 - d3) >= 0. && (d5 - d6) >= 0.)
        {
          const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
          return {t[1] + w * (t[2] - t[1]), {{0., 1. - w, w}}};
        }
      const double denominator = va + vb + vc;
      if (!(std::abs(denominator) >
            0.)) // a degenerate triangle: its first point
        return {t[0], {{1., 0., 0.}}};
      const double v = vb / denominator, w = vc / denominator;
      return {t[0] + v * ab + w * ac, {{1. - v - w, v, w}}};
    }

    namespace
    {
      double
      distance_to_box(const Point<3> &p, const BoundingBox<3> &box)
      {
        double sum = 0.;
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double outside =
              std::max({box.get_boundary_points().first[d] - p[d],
                        p[d] - box.get_boundary_points().second[d],
                        0.});
            sum += outside * outside;
          }
        return std::sqrt(sum);
      }
    } // namespace

    TriangleSearch::TriangleSearch(const Surface &surface)
        : surface(surface)
    {
      std::vector<Box> boxes;
      boxes.reserve(surface.triangles.size());
      for (unsigned int t = 0; t < surface.triangles.size(); ++t)
        {
          const auto &tri = surface.triangles[t];
          boxes.emplace_back(BoundingBox<3>(
                               std::vector<Point<3>>{surface.points[tri[0]],
                                                     surface.points[tri[1]],
                                                     surface.points[tri[2]]}),
                             t);
        }
      tree = pack_rtree(boxes);
    }

    TriangleSearch::Hit
    TriangleSearch::closest(const Point<3> &p) const
    {
      Hit best;
      best.distance = std::numeric_limits<double>::max();
      best.triangle = numbers::invalid_unsigned_int;
      // The k nearest boxes; if the farthest of them could still hold a
      // closer point than the best found, look at more.
      std::vector<Box> boxes;
      for (unsigned int k = 8;; k *= 4)
        {
          boxes.clear();
          tree.query(boost::geometry::index::nearest(p, k),
                     std::back_inserter(boxes));
          double farthest_box = 0.;
          for (const Box &box : boxes)
            {
              farthest_box =
                std::max(farthest_box, distance_to_box(p, box.first));
              const auto &tri = surface.triangles[box.second];
              const auto [point, barycentric] =
                closest_point_on_triangle(p,
                                          {{surface.points[tri[0]],
                                            surface.points[tri[1]],
                                            surface.points[tri[2]]}});
              const double distance = p.distance(point);
              if (distance < best.distance)
                {
                  best.triangle    = box.second;
                  best.point       = point;
                  best.barycentric = barycentric;
                  best.distance    = distance;
                }
            }
          if (boxes.size() < k || farthest_box >= best.distance)
            break;
        }
      return best;
    }

    std::vector<Tensor<1, 3>>
    point_normals(const Surface &surface)
    {
      std::vector<Tensor<1, 3>> normals(surface.points.size());
      double                    enclosed_volume = 0.;
      for (const auto &tri : surface.triangles)
        {
          const Point<3> &a = surface.points[tri[0]],
                         &b = surface.points[tri[1]],
                         &c = surface.points[tri[2]];
          // Twice the area along the normal: area weights for free.
          const Tensor<1, 3> n = cross_product_3d(b - a, c - a);
          for (const unsigned int i : tri)
            normals[i] += n;
          enclosed_volume += n * Tensor<1, 3>(a) / 6.;
        }
      // Closed surfaces (every edge in two triangles) are turned outwards;
      // an open one keeps its winding, since it encloses nothing.
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> edges;
      for (const auto &tri : surface.triangles)
        for (unsigned int e = 0; e < 3; ++e)
          ++edges[std::minmax(tri[e], tri[(e + 1) % 3])];
      const bool closed =
        !edges.empty() &&
        std::all_of(edges.begin(), edges.end(), [](const auto &e) {
          return e.second == 2;
        });
      const double sign = (closed && enclosed_volume < 0.) ? -1. : 1.;
      for (auto &n : normals)
        {
          const double norm = n.norm();
          if (norm > 0.)
            n *= sign / norm;
        }
      return normals;
    }

    void
    check_manifold(const Surface &surface, const std::string &what)
    {
      if (surface.triangles.empty())
        throw Error(what + ": the surface has no triangles.");
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> edges;
      for (unsigned int t = 0; t < surface.triangles.size(); ++t)
        {
          const auto &tri = surface.triangles[t];
          for (unsigned int e = 0; e < 3; ++e)
            {
              if (tri[e] >= surface.points.size())
                {
                  std::ostringstream m;
                  m << what << ": triangle " << t << " names point " << tri[e]
                    << ", but there are " << surface.points.size()
                    << " points.";
                  throw Error(m.str());
                }
              if (tri[e] == tri[(e + 1) % 3])
                {
                  std::ostringstream m;
                  m << what << ": triangle " << t << " repeats point " << tri[e]
                    << '.';
                  throw Error(m.str());
                }
            }
          for (unsigned int e = 0; e < 3; ++e)
            if (++edges[std::minmax(tri[e], tri[(e + 1) % 3])] == 3)
              {
                std::ostringstream m;
                m << what << ": the surface is not manifold: the edge between "
                  << "points " << std::min(tri[e], tri[(e + 1) % 3]) << " and "
                  << std::max(tri[e], tri[(e + 1) % 3])
                  << " belongs to more than two triangles (triangle " << t
                  << " is the third).";
                throw Error(m.str());
              }
        }
      for (const Point<3> &p : surface.points)
        for (unsigned int d = 0; d < 3; ++d)
          if (!std::isfinite(p[d]))
            throw Error(what + ": a point's coordinate is not finite.");
    }
  } // namespace SurfaceMapping
} // namespace softface

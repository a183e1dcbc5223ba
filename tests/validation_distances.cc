// Distances between surfaces (Mollemans et al. 2007, Sec. 3.5.1): a surface
// moved by d along its normals is at signed distance d from the original (a
// sphere moved outwards, exactly, since the vertex is the closest point of the
// inscribed polyhedron; a plane either way); the statistics of a small distance
// map against values computed by hand; masks; a non-manifold surface refused.

#include <softface/core/error.h>
#include <softface/validation/distances.h>

#include "surfaces.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(validation_distances)
{
  const auto sphere =
    softface_tests::transformed(softface_tests::unit_icosphere(4),
                                [](const Point<3> &p) { return 40. * p; });
  const double d = 0.7;
  for (const double sign : {1., -1.})
    {
      const auto moved =
        softface_tests::transformed(sphere, [&](const Point<3> &p) {
          return p + sign * d * p / p.norm();
        });
      const auto distances = Validation::signed_distances(moved.points, sphere);
      double     error = 0., largest = 0.;
      unsigned int n_negative = 0;
      for (const double x : distances)
        {
          error   = std::max(error, std::abs(x - sign * d));
          largest = std::max(largest, std::abs(x));
          n_negative += (x < 0.);
        }
      const std::string name =
        std::string("sphere moved ") + (sign > 0 ? "out" : "in") + "wards";
      softface_tests::check_equal(name + ": points behind",
                                  n_negative,
                                  sign > 0 ? 0 : moved.points.size());
      if (sign > 0)
        softface_tests::check_below(name + ": max |distance - d| mm",
                                    error,
                                    1e-12);
      else
        // Inside, a face of the polyhedron may be closer than its vertex.
        softface_tests::check_below(name + ": max |distance| mm",
                                    largest,
                                    d + 1e-12);
    }

  // A flat patch (normal +z by its winding) moved up and down.
  SurfaceMapping::Surface plane;
  const unsigned int      n = 21;
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int i = 0; i < n; ++i)
      plane.points.emplace_back(i * 1., j * 1., 0.);
  for (unsigned int j = 0; j + 1 < n; ++j)
    for (unsigned int i = 0; i + 1 < n; ++i)
      {
        const unsigned int a = j * n + i;
        plane.triangles.push_back({{a, a + 1, a + n + 1}});
        plane.triangles.push_back({{a, a + n + 1, a + n}});
      }
  for (const double shift : {0.4, -0.4})
    {
      const auto moved =
        softface_tests::transformed(plane, [&](const Point<3> &p) {
          return p + Point<3>(0, 0, shift);
        });
      double error = 0.;
      for (const double x : Validation::signed_distances(moved.points, plane))
        error = std::max(error, std::abs(x - shift));
      softface_tests::check_below("plane moved by " +
                                    softface_tests::rounded(shift) +
                                    ": max |distance - shift| mm",
                                  error,
                                  1e-12);
    }

  // Statistics by hand: d = -3, 1, 2, -0.5, 4; |d| sorted 0.5 1 2 3 4;
  // mean 0.7, mean |d| 2.1, variance (13.69 + 0.09 + 1.69 + 1.44 + 10.89)/5
  // = 5.56, max 4, p50 = 2, p90 = 3 + 0.6 (4 - 3) = 3.6, p95 = 3.8.
  const std::vector<double>   values = {-3., 1., 2., -0.5, 4.};
  const std::vector<Point<3>> where  = {
     {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
  const auto s = Validation::statistics(values, where, Validation::Mask());
  const std::vector<std::pair<std::string, std::pair<double, double>>> by_hand =
    {{"mean", {s.mean, 0.7}},
     {"mean |d|", {s.mean_absolute, 2.1}},
     {"variance", {s.variance, 5.56}},
     {"max |d|", {s.max_absolute, 4.}},
     {"p50", {s.p50, 2.}},
     {"p90", {s.p90, 3.6}},
     {"p95", {s.p95, 3.8}}};
  for (const auto &[name, value] : by_hand)
    softface_tests::check_below(name + " - by hand",
                                std::abs(value.first - value.second),
                                1e-14);

  // A mask removing x in [1.5, 4.5]: d = -3, 1 left.
  const auto mask =
    Validation::Mask::parse("1.5, -1, -1; 4.5, 1, 1", "Skin/Masked boxes");
  const auto masked = Validation::statistics(values, where, mask);
  softface_tests::check_equal("points left by the mask", masked.n, 2);
  softface_tests::check_below("masked p50 - 2",
                              std::abs(masked.p50 - 2.),
                              1e-14);
  for (const std::string &text :
       {std::string("-1, -1, -1; 5, 1, 1"), std::string("1, 2; 3, 4, 5")})
    try
      {
        Validation::statistics(
          values, where, Validation::Mask::parse(text, "Skin/Masked boxes"));
        deallog << "mask '" << text << "' accepted (wrong)" << std::endl;
      }
    catch (const Error &e)
      {
        deallog << e.what() << std::endl;
      }

  // Three triangles on one edge.
  SurfaceMapping::Surface fin;
  fin.points    = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.triangles = {{{0, 1, 2}}, {{1, 0, 3}}, {{0, 1, 4}}};
  try
    {
      SurfaceMapping::check_manifold(fin, "fin.ply");
      deallog << "non-manifold surface accepted (wrong)" << std::endl;
    }
  catch (const Error &e)
    {
      deallog << e.what() << std::endl;
    }
}

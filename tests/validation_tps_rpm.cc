// TPS-RPM correspondences to a continuous surface (validation; Mollemans et al.
// 2007, Sec. 3.5.1). A face-like height field of 120 x 150 mm (a nose, a chin,
// some waviness) sampled at 5000 random points is matched to the same surface
// triangulated on a 1 mm grid: the distances are the grid's chords (near zero;
// the point-to-point matching of two samplings slid 2 mm along the surface).
// Matched to the surface moved by a known smooth warp, the percentiles of
// the distances to the corresponding points come close to those to the true
// partners (the warped points), which closest points underestimate: a
// sinusoidal warp of up to 0.67 mm and a chin advanced by up to 1.1 mm.
// Points whose part of the surface the target lacks end as outliers. The
// run is deterministic; the subsample is spread; bad input is refused.

#include <softface/core/error.h>
#include <softface/validation/tps_rpm.h>

#include "tests.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

using namespace softface;

namespace
{
  // Uniform in (0, 1) from mt19937's raw output, which the standard fixes
  // (unlike its distributions).
  class Uniform
  {
  public:
    explicit Uniform(const unsigned int seed)
        : engine(seed)
    {}
    double
    operator()()
    {
      return (engine() + 0.5) / 4294967296.;
    }

  private:
    std::mt19937 engine;
  };

  double
  face_height(const double x, const double y)
  {
    return -x * x / 90. - y * y / 250. +
           22. * std::exp(-(x * x + (y - 5.) * (y - 5.)) / 200.) +
           8. * std::exp(-(x * x + (y + 55.) * (y + 55.)) / 300.) +
           3. * std::cos(x / 12.) * std::cos(y / 15.);
  }

  // n random points of the face.
  Eigen::MatrixX3d
  face(const unsigned int n, const unsigned int seed)
  {
    Uniform          u(seed);
    Eigen::MatrixX3d p(n, 3);
    for (unsigned int i = 0; i < n; ++i)
      {
        const double x = 120. * u() - 60., y = 150. * u() - 75.;
        p.row(i) << x, y, face_height(x, y);
      }
    return p;
  }

  using Warp = std::function<Eigen::RowVector3d(const Eigen::RowVector3d &)>;

  // Smooth, on a 30 mm scale, up to 0.67 mm.
  Eigen::RowVector3d
  sinusoidal(const Eigen::RowVector3d &x)
  {
    return x + 0.1 * Eigen::RowVector3d(3.5 * std::sin(x[1] / 30. + 0.3) +
                                          std::sin(x[2] / 25. + 0.7),
                                        3.5 * std::sin(x[2] / 30. + 1.1) +
                                          std::sin(x[0] / 25.),
                                        3.5 * std::sin(x[0] / 30. + 2.) +
                                          std::sin(x[1] / 25. + 1.3));
  }

  // The chin (y = -55 mm) forward by 1 mm and up by 0.4 mm, fading over
  // 25 mm.
  Eigen::RowVector3d
  chin_advanced(const Eigen::RowVector3d &x)
  {
    const double g =
      std::exp(-(x[0] * x[0] + (x[1] + 55.) * (x[1] + 55.)) / (2. * 25. * 25.));
    return x + g * Eigen::RowVector3d(0., 0.4, 1.);
  }

  Eigen::RowVector3d
  unmoved(const Eigen::RowVector3d &x)
  {
    return x;
  }

  // The face as a triangle surface on a 1 mm grid, its vertices moved by
  // @p warp; rows with y > y_max left out.
  SurfaceMapping::Surface
  face_surface(const Warp &warp, const double y_max = 75.)
  {
    SurfaceMapping::Surface surface;
    const unsigned int      nx = 121, ny = std::lround(y_max + 75.) + 1;
    for (unsigned int j = 0; j < ny; ++j)
      for (unsigned int i = 0; i < nx; ++i)
        {
          const double             x = -60. + i, y = -75. + j;
          const Eigen::RowVector3d p = warp({x, y, face_height(x, y)});
          surface.points.emplace_back(p[0], p[1], p[2]);
        }
    for (unsigned int j = 0; j + 1 < ny; ++j)
      for (unsigned int i = 0; i + 1 < nx; ++i)
        {
          const unsigned int a = j * nx + i;
          surface.triangles.push_back({{a, a + 1, a + nx + 1}});
          surface.triangles.push_back({{a, a + nx + 1, a + nx}});
        }
    return surface;
  }

  double
  percentile_90(const Eigen::VectorXd &values)
  {
    std::vector<double> v(values.data(), values.data() + values.size());
    std::sort(v.begin(), v.end());
    const double      position = 0.9 * (v.size() - 1);
    const std::size_t below    = position;
    return below + 1 < v.size() ?
             v[below] + (position - below) * (v[below + 1] - v[below]) :
             v[below];
  }

  void
  expect_error(const std::string &what, const std::function<void()> &run)
  {
    try
      {
        run();
        dealii::deallog << what << " accepted (wrong)" << std::endl;
      }
    catch (const Error &e)
      {
        dealii::deallog << e.what() << std::endl;
      }
  }
} // namespace

SOFTFACE_TEST(validation_tps_rpm)
{
  const Eigen::MatrixX3d on_face = face(5000, 21);

  // Another sampling of the same surface: every point's partner is itself.
  {
    const auto result = Validation::tps_rpm(on_face, face_surface(unmoved));
    const std::string name = "same surface: ";
    softface_tests::check_equal(name + "fitted points",
                                result.n_fit_points,
                                5000);
    softface_tests::check_equal(name + "spline centres",
                                result.n_control_points,
                                300);
    softface_tests::check_below(name + "p90 |source - correspondence| mm",
                                percentile_90(result.distance),
                                0.1);
    softface_tests::check_below(
      name + "max |distance - |source - correspondence|| mm",
      (result.distance - (result.correspondence - on_face).rowwise().norm())
        .cwiseAbs()
        .maxCoeff(),
      1e-12);
  }

  // Known warps: the distances to the corresponding points against those to
  // the true partners (exact) and to the closest points.
  for (const auto &[name, warp] : std::vector<std::pair<std::string, Warp>>{
         {"sinusoidal warp: ", sinusoidal}, {"chin advanced: ", chin_advanced}})
    {
      const auto target = face_surface(warp);
      const auto result = Validation::tps_rpm(on_face, target);
      const SurfaceMapping::TriangleSearch search(target);
      Eigen::VectorXd exact(on_face.rows()), closest(on_face.rows()),
        partner(on_face.rows());
      for (Eigen::Index i = 0; i < on_face.rows(); ++i)
        {
          exact[i] = (warp(on_face.row(i)) - on_face.row(i)).norm();
          partner[i] =
            (result.correspondence.row(i) - warp(on_face.row(i))).norm();
          closest[i] =
            search
              .closest(Point<3>(on_face(i, 0), on_face(i, 1), on_face(i, 2)))
              .distance;
        }
      const double p90 = percentile_90(exact);
      softface_tests::print(name + "exact p90 mm", p90);
      softface_tests::check_below(name + "closest-point p90 / exact p90",
                                  percentile_90(closest) / p90,
                                  0.9);
      softface_tests::check_within(name + "TPS-RPM p90 / exact p90",
                                   percentile_90(result.distance) / p90,
                                   0.9,
                                   1.1);
      std::vector<double> sorted(partner.data(),
                                 partner.data() + partner.size());
      std::nth_element(sorted.begin(),
                       sorted.begin() + sorted.size() / 2,
                       sorted.end());
      softface_tests::print(name + "median |correspondence - true partner| mm",
                            sorted[sorted.size() / 2],
                            2);
    }

  // The target lacks the strip y > 50 mm: points there are outliers, the
  // others matched.
  {
    const auto result =
      Validation::tps_rpm(on_face, face_surface(sinusoidal, 50.));
    unsigned int n_strip = 0, n_outliers = 0, n_kept = 0, n_matched = 0;
    for (Eigen::Index i = 0; i < on_face.rows(); ++i)
      if (on_face(i, 1) > 55.)
        {
          ++n_strip;
          n_outliers += result.match_weight[i] < 0.5;
        }
      else if (on_face(i, 1) < 45.)
        {
          ++n_kept;
          n_matched += result.match_weight[i] > 0.5;
        }
    const std::string name = "target without y > 50 mm: ";
    softface_tests::check_above(name + "fraction of y > 55 with weight < 0.5",
                                n_outliers / double(n_strip),
                                0.99,
                                3);
    softface_tests::check_above(name + "fraction of y < 45 with weight > 0.5",
                                n_matched / double(n_kept),
                                0.99,
                                3);
  }

  // Deterministic: a second run gives the same bits.
  {
    const Eigen::MatrixX3d points = face(300, 5);
    const auto             target = face_surface(chin_advanced);
    const auto             first  = Validation::tps_rpm(points, target);
    const auto             second = Validation::tps_rpm(points, target);
    softface_tests::check_equal("two runs: same warped points",
                                first.warped_source == second.warped_source &&
                                  first.match_weight == second.match_weight,
                                1);
  }

  // The subsample: spread, in ascending order, all points when asked for
  // more.
  {
    const auto chosen = Validation::subsample(on_face, 100);
    softface_tests::check_equal("subsample of 100: size", chosen.size(), 100);
    double closest   = std::numeric_limits<double>::infinity();
    bool   ascending = true;
    for (std::size_t a = 0; a < chosen.size(); ++a)
      for (std::size_t b = a + 1; b < chosen.size(); ++b)
        {
          ascending = ascending && chosen[a] < chosen[b];
          closest =
            std::min(closest,
                     (on_face.row(chosen[a]) - on_face.row(chosen[b])).norm());
        }
    softface_tests::check_equal("subsample of 100: ascending", ascending, 1);
    softface_tests::check_above("subsample of 100: closest pair mm",
                                closest,
                                10.,
                                2);
    softface_tests::check_equal("subsample of 9000 of 5000: size",
                                Validation::subsample(on_face, 9000).size(),
                                5000);
  }

  // Bad input.
  const Eigen::MatrixX3d        points  = face(20, 1);
  const SurfaceMapping::Surface surface = face_surface(unmoved, -70.);
  Eigen::MatrixX3d              broken  = points;
  broken(4, 1)    = std::numeric_limits<double>::quiet_NaN();
  const auto with = [](const auto &change) {
    Validation::TpsRpmParameters p;
    change(p);
    return p;
  };
  expect_error("an empty source",
               [&] { Validation::tps_rpm(Eigen::MatrixX3d(0, 3), surface); });
  expect_error("a NaN source point",
               [&] { Validation::tps_rpm(broken, surface); });
  expect_error("a target without triangles",
               [&] { Validation::tps_rpm(points, SurfaceMapping::Surface()); });
  expect_error("annealing rate 1.5", [&] {
    Validation::tps_rpm(points, surface, with([](auto &p) {
                          p.annealing_rate = 1.5;
                        }));
  });
  expect_error("final temperature -1", [&] {
    Validation::tps_rpm(points, surface, with([](auto &p) {
                          p.final_temperature = -1.;
                        }));
  });
  expect_error("initial temperature below the final one", [&] {
    Validation::tps_rpm(points, surface, with([](auto &p) {
                          p.initial_temperature = 0.001;
                        }));
  });
  expect_error("no control points", [&] {
    Validation::tps_rpm(points, surface, with([](auto &p) {
                          p.control_points = 0;
                        }));
  });
  expect_error("no fitted points", [&] {
    Validation::tps_rpm(points, surface, with([](auto &p) {
                          p.fit_points = 0;
                        }));
  });
  expect_error("a subsample of 0 points",
               [&] { Validation::subsample(points, 0); });
}

// TPS-RPM correspondences (validation, seed 3.5.1). Points on an ellipsoid
// of 60 x 80 x 100 mm, moved by a smooth warp (up to 6.7 mm, varying on a 30
// mm scale) and shuffled, are matched back point for point. A face-like patch
// whose target lacks a strip is still matched, and the points of the strip
// end as outliers. Against another sampling of the warped ellipsoid the
// correspondences lie on the right surface (small error along its normal;
// along it the motion is barely in the data, so only a loose bound). The
// subsample is spread and deterministic; bad input is refused.

#include <softface/core/error.h>
#include <softface/validation/tps_rpm.h>

#include "tests.h"

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
    unsigned int
    below(const unsigned int n)
    {
      return engine() % n;
    }

  private:
    std::mt19937 engine;
  };

  const double semi_axes[3] = {30., 40., 50.};

  Eigen::MatrixX3d
  ellipsoid(const unsigned int n, const unsigned int seed)
  {
    Uniform          u(seed);
    Eigen::MatrixX3d p(n, 3);
    for (unsigned int i = 0; i < n; ++i)
      {
        const double z = 2. * u() - 1., phi = 2. * M_PI * u(),
                     s = std::sqrt(1. - z * z);
        p.row(i) << semi_axes[0] * s * std::cos(phi),
          semi_axes[1] * s * std::sin(phi), semi_axes[2] * z;
      }
    return p;
  }

  // A height field of 120 x 150 mm with a nose, a chin and some waviness.
  Eigen::MatrixX3d
  face(const unsigned int n, const unsigned int seed)
  {
    Uniform          u(seed);
    Eigen::MatrixX3d p(n, 3);
    for (unsigned int i = 0; i < n; ++i)
      {
        const double x = 120. * u() - 60., y = 150. * u() - 75.;
        const double z =
          -x * x / 90. - y * y / 250. +
          22. * std::exp(-(x * x + (y - 5.) * (y - 5.)) / 200.) +
          8. * std::exp(-(x * x + (y + 55.) * (y + 55.)) / 300.) +
          3. * std::cos(x / 12.) * std::cos(y / 15.);
        p.row(i) << x, y, z;
      }
    return p;
  }

  Eigen::RowVector3d
  warp(const Eigen::RowVector3d &x)
  {
    return x + Eigen::RowVector3d(
                 3.5 * std::sin(x[1] / 30. + 0.3) + std::sin(x[2] / 25. + 0.7),
                 3.5 * std::sin(x[2] / 30. + 1.1) + std::sin(x[0] / 25.),
                 3.5 * std::sin(x[0] / 30. + 2.) + std::sin(x[1] / 25. + 1.3));
  }

  Eigen::MatrixX3d
  warped(const Eigen::MatrixX3d &points)
  {
    Eigen::MatrixX3d moved(points.rows(), 3);
    for (Eigen::Index i = 0; i < points.rows(); ++i)
      moved.row(i) = warp(points.row(i));
    return moved;
  }

  // The unit normal of the warped ellipsoid at warp(x): J^-T grad F(x).
  Eigen::Vector3d
  warped_ellipsoid_normal(const Eigen::RowVector3d &x)
  {
    Eigen::Matrix3d jacobian = Eigen::Matrix3d::Identity();
    jacobian(0, 1)           = 3.5 / 30. * std::cos(x[1] / 30. + 0.3);
    jacobian(0, 2)           = std::cos(x[2] / 25. + 0.7) / 25.;
    jacobian(1, 0)           = std::cos(x[0] / 25.) / 25.;
    jacobian(1, 2)           = 3.5 / 30. * std::cos(x[2] / 30. + 1.1);
    jacobian(2, 0)           = 3.5 / 30. * std::cos(x[0] / 30. + 2.);
    jacobian(2, 1)           = std::cos(x[1] / 25. + 1.3) / 25.;
    Eigen::Vector3d gradient;
    for (unsigned int d = 0; d < 3; ++d)
      gradient[d] = x[d] / (semi_axes[d] * semi_axes[d]);
    return jacobian.transpose().partialPivLu().solve(gradient).normalized();
  }

  std::vector<unsigned int>
  permutation(const unsigned int n, const unsigned int seed)
  {
    Uniform                   u(seed);
    std::vector<unsigned int> order(n);
    for (unsigned int i = 0; i < n; ++i)
      order[i] = i;
    for (unsigned int i = n - 1; i > 0; --i)
      std::swap(order[i], order[u.below(i + 1)]);
    return order;
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
  const unsigned int n = 1500;

  // The same points, warped and shuffled.
  {
    const Eigen::MatrixX3d source = ellipsoid(n, 1);
    const Eigen::MatrixX3d moved  = warped(source);
    const auto             order  = permutation(n, 7);
    Eigen::MatrixX3d       target(n, 3);
    for (unsigned int i = 0; i < n; ++i)
      target.row(i) = moved.row(order[i]);
    const auto result = Validation::tps_rpm(source, target);

    const Eigen::VectorXd error =
      (result.correspondence - moved).rowwise().norm();
    const std::string name = "ellipsoid, same points warped: ";
    softface_tests::check_equal(name + "iterations", result.iterations, 255);
    // Two digits: a point more or less does not change the output.
    softface_tests::check_above(name + "fraction matched within 0.1 mm",
                                (error.array() <= 0.1).cast<double>().mean(),
                                0.99,
                                2);
    softface_tests::check_below(name + "mean |correspondence - true| mm",
                                error.mean(),
                                0.01);
    softface_tests::check_below(
      name + "mean |warped source - true| mm",
      (result.warped_source - moved).rowwise().norm().mean(),
      0.05,
      1);
    softface_tests::check_below(
      name + "max |distance - |source - correspondence|| mm",
      (result.distance - (result.correspondence - source).rowwise().norm())
        .cwiseAbs()
        .maxCoeff(),
      1e-12);
  }

  // The face's target lacks the strip y > 50 mm: its points are outliers.
  {
    const Eigen::MatrixX3d    source = face(n, 3);
    const Eigen::MatrixX3d    moved  = warped(source);
    std::vector<unsigned int> kept;
    for (const unsigned int i : permutation(n, 11))
      if (source(i, 1) < 50.)
        kept.push_back(i);
    Eigen::MatrixX3d target(kept.size(), 3);
    for (std::size_t k = 0; k < kept.size(); ++k)
      target.row(k) = moved.row(kept[k]);
    const auto result = Validation::tps_rpm(source, target);

    unsigned int n_kept = 0, n_matched = 0, n_outliers = 0;
    double       weight_kept = 0.;
    for (unsigned int i = 0; i < n; ++i)
      if (source(i, 1) < 50.)
        {
          ++n_kept;
          weight_kept += result.match_weight[i];
          n_matched +=
            (result.correspondence.row(i) - moved.row(i)).norm() <= 0.1;
        }
      else
        n_outliers += result.match_weight[i] < 0.5;
    const std::string name = "face, target without y > 50 mm: ";
    softface_tests::check_equal(name + "points cut away", n - n_kept, 236);
    softface_tests::check_above(name + "fraction kept matched within 0.1 mm",
                                n_matched / double(n_kept),
                                0.99,
                                2);
    softface_tests::check_above(name + "mean match weight of those kept",
                                weight_kept / n_kept,
                                0.95,
                                2);
    softface_tests::check_above(name +
                                  "fraction cut away with match weight < 0.5",
                                n_outliers / double(n - n_kept),
                                0.99,
                                2);
  }

  // Another sampling of the warped ellipsoid.
  {
    const Eigen::MatrixX3d source = ellipsoid(n, 1);
    const Eigen::MatrixX3d moved  = warped(source);
    const auto result = Validation::tps_rpm(source, warped(ellipsoid(n, 2)));
    double     error = 0., normal_error = 0., displacement = 0.;
    for (unsigned int i = 0; i < n; ++i)
      {
        const Eigen::RowVector3d e =
          result.correspondence.row(i) - moved.row(i);
        error += e.norm();
        normal_error +=
          std::abs(e.dot(warped_ellipsoid_normal(source.row(i)).transpose()));
        displacement += (moved.row(i) - source.row(i)).norm();
      }
    const std::string name = "ellipsoid, another sampling: ";
    softface_tests::print(name + "mean |true - source| mm",
                          displacement / n,
                          2);
    softface_tests::check_below(name + "mean |correspondence - true| mm",
                                error / n,
                                3.5,
                                1);
    softface_tests::check_below(
      name + "mean |correspondence - true| along the normal mm",
      normal_error / n,
      0.2,
      1);
  }

  // Deterministic: a second run gives the same bits.
  {
    const Eigen::MatrixX3d source = ellipsoid(300, 5);
    const Eigen::MatrixX3d target = warped(ellipsoid(300, 6));
    const auto             first  = Validation::tps_rpm(source, target);
    const auto             second = Validation::tps_rpm(source, target);
    softface_tests::check_equal("two runs: same warped points",
                                first.warped_source == second.warped_source &&
                                  first.match_weight == second.match_weight,
                                1);
  }

  // The subsample: spread, in ascending order, all points when asked for
  // more.
  {
    const Eigen::MatrixX3d points = ellipsoid(n, 1);
    const auto             chosen = Validation::subsample(points, 100);
    softface_tests::check_equal("subsample of 100: size", chosen.size(), 100);
    double closest   = std::numeric_limits<double>::infinity();
    bool   ascending = true;
    for (std::size_t a = 0; a < chosen.size(); ++a)
      for (std::size_t b = a + 1; b < chosen.size(); ++b)
        {
          ascending = ascending && chosen[a] < chosen[b];
          closest =
            std::min(closest,
                     (points.row(chosen[a]) - points.row(chosen[b])).norm());
        }
    softface_tests::check_equal("subsample of 100: ascending", ascending, 1);
    softface_tests::check_above("subsample of 100: closest pair mm",
                                closest,
                                10.,
                                2);
    softface_tests::check_equal("subsample of 5000 of 1500: size",
                                Validation::subsample(points, 5000).size(),
                                n);
  }

  // Bad input.
  const Eigen::MatrixX3d points = ellipsoid(20, 1);
  Eigen::MatrixX3d       broken = points;
  broken(4, 1)                  = std::numeric_limits<double>::quiet_NaN();
  const auto with               = [](const auto &change) {
    Validation::TpsRpmParameters p;
    change(p);
    return p;
  };
  expect_error("an empty source",
               [&] { Validation::tps_rpm(Eigen::MatrixX3d(0, 3), points); });
  expect_error("a NaN target point",
               [&] { Validation::tps_rpm(points, broken); });
  expect_error("annealing rate 1.5", [&] {
    Validation::tps_rpm(points, points, with([](auto &p) {
                          p.annealing_rate = 1.5;
                        }));
  });
  expect_error("final temperature -1", [&] {
    Validation::tps_rpm(points, points, with([](auto &p) {
                          p.final_temperature = -1.;
                        }));
  });
  expect_error("initial temperature below the final one", [&] {
    Validation::tps_rpm(points, points, with([](auto &p) {
                          p.initial_temperature = 0.001;
                        }));
  });
  expect_error("no control points", [&] {
    Validation::tps_rpm(points, points, with([](auto &p) {
                          p.control_points = 0;
                        }));
  });
  expect_error("a subsample of 0 points",
               [&] { Validation::subsample(points, 0); });
}

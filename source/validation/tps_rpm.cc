// Corresponding points of a predicted skin on the post-operative skin's
// surface by a TPS-RPM variant (validation; Mollemans et al. 2007, Sec. 3.5.1):
// a thin-plate spline annealed towards the target's closest points, with an
// outlier class. Eigen, deal.II's R-tree (TriangleSearch) and threads.

#include <softface/core/error.h>
#include <softface/core/threads.h>
#include <softface/validation/thin_plate_spline.h>
#include <softface/validation/tps_rpm.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>

namespace softface
{
  namespace Validation
  {
    namespace
    {
      void
      require(const bool valid, const std::string &what, const double value)
      {
        if (!valid)
          {
            std::ostringstream m;
            m << "TPS-RPM: " << what << ", not " << value << ".";
            throw Error(m.str());
          }
      }

      void
      check(const Eigen::MatrixX3d        &source,
            const SurfaceMapping::Surface &target,
            const TpsRpmParameters        &p)
      {
        if (source.rows() == 0)
          throw Error("TPS-RPM: the source point set is empty.");
        for (Eigen::Index i = 0; i < source.rows(); ++i)
          if (!source.row(i).allFinite())
            {
              std::ostringstream m;
              m << "TPS-RPM: source point " << i
                << " has a non-finite coordinate (" << source(i, 0) << ", "
                << source(i, 1) << ", " << source(i, 2) << ").";
              throw Error(m.str());
            }
        if (target.triangles.empty())
          throw Error("TPS-RPM: the target surface has no triangles.");
        // Written so that NaN fails every check.
        const auto positive = [](const double x) {
          return x > 0. && std::isfinite(x);
        };
        const auto non_negative = [](const double x) {
          return x >= 0. && std::isfinite(x);
        };
        require(std::isfinite(p.initial_temperature),
                "the initial temperature must be finite (<= 0: automatic)",
                p.initial_temperature);
        require(positive(p.final_temperature),
                "the final temperature must be positive (mm^2)",
                p.final_temperature);
        require(p.initial_temperature <= 0. ||
                  p.initial_temperature >= p.final_temperature,
                "the initial temperature must not be below the final one",
                p.initial_temperature);
        require(p.annealing_rate > 0. && p.annealing_rate < 1.,
                "the annealing rate must lie in (0, 1)",
                p.annealing_rate);
        require(p.iterations_per_temperature >= 1,
                "the iterations per temperature must be at least 1",
                p.iterations_per_temperature);
        require(non_negative(p.lambda_initial),
                "the initial bending weight lambda must be >= 0 (mm)",
                p.lambda_initial);
        require(non_negative(p.lambda_final),
                "the final bending weight lambda must be >= 0 (mm)",
                p.lambda_final);
        require(p.control_points >= 1,
                "the number of control points must be at least 1",
                p.control_points);
        require(p.fit_points >= 1,
                "the number of fitted points must be at least 1",
                p.fit_points);
        require(p.outlier_weight > 0. && p.outlier_weight <= 1.,
                "the outlier weight must lie in (0, 1]",
                p.outlier_weight);
      }

      /// At most @p n of @p n_rows rows, a pseudo-random subset (a partial
      /// Fisher-Yates shuffle by mt19937's raw output, which the standard
      /// fixes), in ascending order.
      std::vector<unsigned int>
      random_subset(const unsigned int n_rows, const unsigned int n)
      {
        std::vector<unsigned int> rows(n_rows);
        for (unsigned int i = 0; i < n_rows; ++i)
          rows[i] = i;
        if (n >= n_rows)
          return rows;
        std::mt19937 engine(20070101);
        for (unsigned int i = 0; i < n; ++i)
          std::swap(rows[i], rows[i + engine() % (n_rows - i)]);
        rows.resize(n);
        std::sort(rows.begin(), rows.end());
        return rows;
      }

      Eigen::MatrixX3d
      rows_of(const Eigen::MatrixX3d &m, const std::vector<unsigned int> &rows)
      {
        Eigen::MatrixX3d result(rows.size(), 3);
        for (std::size_t k = 0; k < rows.size(); ++k)
          result.row(k) = m.row(rows[k]);
        return result;
      }

      /**
       * Where the target surface ends: its edges that belong to one
       * triangle only. A point whose closest point lies on such an edge has
       * no counterpart on the target (a surface cut off by the scan's field
       * of view): it would otherwise be pulled onto the rim.
       */
      class Rim
      {
      public:
        explicit Rim(const SurfaceMapping::Surface &surface)
        {
          std::map<std::pair<unsigned int, unsigned int>, unsigned int> count;
          for (const auto &t : surface.triangles)
            for (unsigned int e = 0; e < 3; ++e)
              ++count[key(t[e], t[(e + 1) % 3])];
          for (const auto &[edge, n] : count)
            if (n == 1)
              edges.insert(edge);
        }

        /// Does the closest point @p hit lie on the rim?
        bool
        holds(const SurfaceMapping::TriangleSearch::Hit &hit,
              const SurfaceMapping::Surface             &surface) const
        {
          if (edges.empty())
            return false;
          const auto &t = surface.triangles[hit.triangle];
          for (unsigned int k = 0; k < 3; ++k)
            if (hit.barycentric[k] <= 1e-9 &&
                edges.count(key(t[(k + 1) % 3], t[(k + 2) % 3])) > 0)
              return true;
          return false;
        }

      private:
        static std::pair<unsigned int, unsigned int>
        key(const unsigned int a, const unsigned int b)
        {
          return {std::min(a, b), std::max(a, b)};
        }

        std::set<std::pair<unsigned int, unsigned int>> edges;
      };

      /// The closest points on @p search's surface to the rows of @p points
      /// (which are relative to @p centre), relative to @p centre too, and
      /// whether each lies on the surface's rim.
      Eigen::MatrixX3d
      closest_points(const SurfaceMapping::TriangleSearch &search,
                     const SurfaceMapping::Surface        &target,
                     const Rim                            &rim,
                     const Eigen::MatrixX3d               &points,
                     const Eigen::RowVector3d             &centre,
                     std::vector<bool>                    &on_rim)
      {
        Eigen::MatrixX3d   result(points.rows(), 3);
        std::vector<char>  rim_hit(points.rows(), 0);
        const unsigned int n_tasks = 64;
        Threads::run_tasks(n_tasks, [&](const unsigned int task) {
          const Eigen::Index begin = points.rows() * task / n_tasks,
                             end   = points.rows() * (task + 1) / n_tasks;
          for (Eigen::Index a = begin; a < end; ++a)
            {
              const Eigen::RowVector3d x = points.row(a) + centre;
              const auto hit = search.closest(Point<3>(x[0], x[1], x[2]));
              for (unsigned int d = 0; d < 3; ++d)
                result(a, d) = hit.point[d] - centre[d];
              rim_hit[a] = rim.holds(hit, target);
            }
        });
        on_rim.assign(rim_hit.begin(), rim_hit.end());
        return result;
      }

      /// g / (g + w), g = exp(-d^2 / (2 T)).
      double
      inlier_weight(const double squared_distance,
                    const double temperature,
                    const double outlier_weight)
      {
        const double g = std::exp(-squared_distance / (2. * temperature));
        return g / (g + outlier_weight);
      }
    } // namespace


    std::vector<unsigned int>
    subsample(const Eigen::MatrixX3d &points, const unsigned int n)
    {
      if (points.rows() == 0)
        throw Error("TPS-RPM: cannot subsample an empty point set.");
      if (n == 0)
        throw Error("TPS-RPM: cannot subsample to zero points.");
      const Eigen::Index        n_points = points.rows();
      std::vector<unsigned int> chosen;
      if (n >= n_points)
        {
          for (Eigen::Index i = 0; i < n_points; ++i)
            chosen.push_back(i);
          return chosen;
        }

      // Farthest-point sampling; maxCoeff() returns the first maximum. It
      // stops early when the points left coincide with chosen ones.
      const Eigen::RowVector3d centroid = points.colwise().mean();
      Eigen::Index             next     = 0;
      (points.rowwise() - centroid).rowwise().squaredNorm().maxCoeff(&next);
      Eigen::VectorXd gap =
        Eigen::VectorXd::Constant(n_points,
                                  std::numeric_limits<double>::infinity());
      while (chosen.size() < n)
        {
          chosen.push_back(next);
          gap = gap.cwiseMin(
            (points.rowwise() - points.row(next)).rowwise().squaredNorm());
          if (gap.maxCoeff(&next) == 0.)
            break;
        }
      std::sort(chosen.begin(), chosen.end());
      return chosen;
    }



    TpsRpmResult
    tps_rpm(const Eigen::MatrixX3d        &source_in,
            const SurfaceMapping::Surface &target,
            const TpsRpmParameters        &p)
    {
      check(source_in, target, p);
      const SurfaceMapping::TriangleSearch search(target);
      const Rim                            rim(target);
      std::vector<bool>                    on_rim;

      // About the source's centroid: the spline's affine part is then well
      // conditioned, and its identity is A = I with no translation.
      const Eigen::RowVector3d centroid = source_in.colwise().mean();
      const Eigen::MatrixX3d   source   = source_in.rowwise() - centroid;

      const Eigen::MatrixX3d fitted =
        rows_of(source, random_subset(source.rows(), p.fit_points));
      const Eigen::MatrixX3d control =
        rows_of(fitted, subsample(fitted, p.control_points));
      ThinPlateSpline spline(fitted, control);

      const double t_final   = p.final_temperature;
      double       t_initial = p.initial_temperature;
      if (t_initial <= 0.)
        t_initial =
          std::max(0.04 * source.rowwise().squaredNorm().mean(), t_final);

      TpsRpmResult     result;
      Eigen::MatrixX3d warped = fitted;
      for (double t = t_initial;; t = std::max(t * p.annealing_rate, t_final))
        {
          const double lambda = annealed_weight(
            p.lambda_initial, p.lambda_final, t, t_initial, t_final);
          for (unsigned int i = 0; i < p.iterations_per_temperature; ++i)
            {
              // A point pulls towards its closest target point by its inlier
              // weight; an outlier (or a point beyond the target's rim) stays
              // where the others take it.
              const Eigen::MatrixX3d closest =
                closest_points(search, target, rim, warped, centroid, on_rim);
              Eigen::MatrixX3d goal(warped.rows(), 3);
              for (Eigen::Index a = 0; a < warped.rows(); ++a)
                {
                  const double m =
                    on_rim[a] ?
                      0. :
                      inlier_weight(
                        (closest.row(a) - warped.row(a)).squaredNorm(),
                        t,
                        p.outlier_weight);
                  goal.row(a) = m * closest.row(a) + (1. - m) * warped.row(a);
                }
              spline.fit(goal, lambda, 0.);
              warped = spline.warped();
              ++result.iterations;
            }
          if (t <= t_final)
            break;
        }

      // Every source point: warped by the spline, matched to its closest
      // target point.
      const Eigen::MatrixX3d all_warped = spline.warp(source);
      const Eigen::MatrixX3d closest =
        closest_points(search, target, rim, all_warped, centroid, on_rim);
      result.warped_source  = all_warped.rowwise() + centroid;
      result.correspondence = closest.rowwise() + centroid;
      result.distance = (result.correspondence - source_in).rowwise().norm();
      result.match_weight.resize(source.rows());
      for (Eigen::Index a = 0; a < source.rows(); ++a)
        result.match_weight[a] =
          on_rim[a] ?
            0. :
            inlier_weight((closest.row(a) - all_warped.row(a)).squaredNorm(),
                          t_final,
                          p.outlier_weight);
      result.beyond_rim        = on_rim;
      result.n_fit_points      = fitted.rows();
      result.n_control_points  = control.rows();
      result.final_temperature = t_final;
      return result;
    }
  } // namespace Validation
} // namespace softface

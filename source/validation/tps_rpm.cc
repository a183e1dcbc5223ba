// Non-rigid point correspondences by TPS-RPM (validation, seed 3.5.1): the
// "true" correspondences between a predicted skin and the post-operative one
// (Mollemans et al. 2007 used a variant of the TPS-RPM of Chui and Rangarajan
// 2000, 2003). Deterministic annealing of a softassign match matrix with an
// outlier row and column, alternating with a thin-plate spline fit. For
// surfaces of thousands of points the match matrix is sparse (only target
// points within a few sqrt(T) of a warped source point) and the TPS has a
// bounded number of control points, so one iteration costs milliseconds,
// not a pass over a dense N x K matrix. Eigen and nanoflann only.

#include <softface/core/error.h>
#include <softface/validation/tps_rpm.h>

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace softface
{
  namespace Validation
  {
    namespace
    {
      std::string
      number(const double x)
      {
        std::ostringstream s;
        s << x;
        return s.str();
      }

      void
      check_points(const Eigen::MatrixX3d &points, const std::string &name)
      {
        if (points.rows() == 0)
          throw Error("TPS-RPM: the " + name + " point set is empty.");
        for (Eigen::Index i = 0; i < points.rows(); ++i)
          if (!points.row(i).allFinite())
            throw Error("TPS-RPM: " + name + " point " + std::to_string(i) +
                        " has a non-finite coordinate (" +
                        number(points(i, 0)) + ", " + number(points(i, 1)) +
                        ", " + number(points(i, 2)) + ").");
      }

      void
      require(const bool valid, const std::string &what, const double value)
      {
        if (!valid)
          throw Error("TPS-RPM: " + what + ", not " + number(value) + ".");
      }

      void
      check_parameters(const TpsRpmParameters &p)
      {
        // Written so that NaN fails every check.
        const auto non_negative = [](const double x) {
          return x >= 0. && std::isfinite(x);
        };
        const auto positive = [](const double x) {
          return x > 0. && std::isfinite(x);
        };
        require(std::isfinite(p.initial_temperature),
                "the initial temperature must be finite (<= 0: automatic)",
                p.initial_temperature);
        require(positive(p.final_temperature),
                "the final temperature must be positive (mm^2)",
                p.final_temperature);
        require(p.initial_temperature <= 0. ||
                  p.initial_temperature >= p.final_temperature,
                "the initial temperature must not be below the final one (" +
                  number(p.final_temperature) + " mm^2)",
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
        require(non_negative(p.affine_lambda_initial),
                "the initial affine weight must be >= 0 (mm^2)",
                p.affine_lambda_initial);
        require(non_negative(p.affine_lambda_final),
                "the final affine weight must be >= 0 (mm^2)",
                p.affine_lambda_final);
        require(p.control_points >= 1,
                "the number of control points must be at least 1",
                p.control_points);
        require(p.outlier_weight > 0. && p.outlier_weight <= 1.,
                "the outlier weight must lie in (0, 1]",
                p.outlier_weight);
        require(positive(p.search_radius),
                "the search radius must be positive (in sqrt(T))",
                p.search_radius);
        require(p.sinkhorn_iterations >= 1,
                "the softassign normalisation sweeps must be at least 1",
                p.sinkhorn_iterations);
        require(positive(p.sinkhorn_tolerance),
                "the softassign tolerance must be positive",
                p.sinkhorn_tolerance);
      }

      /// A weight that follows the temperature: @p initial at @p t_initial,
      /// @p final at @p t_final, geometrically in between (linearly in log T
      /// when either weight is zero).
      double
      annealed(const double initial,
               const double final,
               const double t,
               const double t_initial,
               const double t_final)
      {
        const double s = t_initial > t_final ? std::log(t_initial / t) /
                                                 std::log(t_initial / t_final) :
                                               1.;
        if (initial > 0. && final > 0.)
          return initial * std::pow(final / initial, s);
        return initial + s * (final - initial);
      }


      // nanoflann's view of the rows of a matrix.
      struct Cloud
      {
        const Eigen::MatrixX3d &points;

        std::size_t
        kdtree_get_point_count() const
        {
          return points.rows();
        }
        double
        kdtree_get_pt(const std::size_t i, const std::size_t d) const
        {
          return points(i, d);
        }
        template <class BoundingBox>
        bool
        kdtree_get_bbox(BoundingBox &) const
        {
          return false;
        }
      };

      using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
        nanoflann::L2_Simple_Adaptor<double, Cloud>,
        Cloud,
        3,
        unsigned int>;

      // Collects (index, squared distance) within a radius, through the
      // callback interface of radiusSearchCustomCallback(): the same in
      // nanoflann 1.4 and 1.5, unlike radiusSearch().
      class Neighbours
      {
      public:
        explicit Neighbours(const double squared_radius)
            : squared_radius(squared_radius)
        {}
        std::size_t
        size() const
        {
          return found.size();
        }
        bool
        full() const
        {
          return true;
        }
        bool
        addPoint(const double squared_distance, const unsigned int index)
        {
          if (squared_distance < squared_radius)
            found.emplace_back(index, squared_distance);
          return true;
        }
        double
        worstDist() const
        {
          return squared_radius;
        }

        const double                                 squared_radius;
        std::vector<std::pair<unsigned int, double>> found;
      };

      unsigned int
      closest(const KdTree &tree, const Eigen::RowVector3d &x)
      {
        const double query[3]         = {x[0], x[1], x[2]};
        unsigned int index            = 0;
        double       squared_distance = 0.;
        tree.knnSearch(query, 1, &index, &squared_distance);
        return index;
      }


      /**
       * An orthogonal Q whose first columns span those of @p a (n x m, n >=
       * m or not), by Householder reflections: its last n - m columns are an
       * orthonormal basis of the vectors orthogonal to them. (Our own: Eigen
       * 3.4's HouseholderQR draws a false -Wmaybe-uninitialized from GCC
       * 12.)
       */
      Eigen::MatrixXd
      orthogonal_complement(Eigen::MatrixXd a)
      {
        const Eigen::Index n           = a.rows();
        const Eigen::Index m           = std::min(a.rows(), a.cols());
        Eigen::MatrixXd    reflections = Eigen::MatrixXd::Zero(n, m);
        for (Eigen::Index i = 0; i < m; ++i)
          {
            // The reflection I - 2 v v^T taking a(i:, i) to a multiple of
            // e_i; none for a zero column (rank-deficient a).
            Eigen::VectorXd v    = a.col(i).tail(n - i);
            const double    norm = v.norm();
            if (norm == 0.)
              continue;
            v[0] += v[0] < 0. ? -norm : norm;
            v.normalize();
            a.bottomRows(n - i) -=
              2. * v * (v.transpose() * a.bottomRows(n - i));
            reflections.col(i).tail(n - i) = v;
          }
        // Q = H_0 H_1 ... H_{m-1} I, the last reflection applied first.
        Eigen::MatrixXd q = Eigen::MatrixXd::Identity(n, n);
        for (Eigen::Index i = m - 1; i >= 0; --i)
          {
            const Eigen::VectorXd v = reflections.col(i).tail(n - i);
            q.bottomRows(n - i) -=
              2. * v * (v.transpose() * q.bottomRows(n - i));
          }
        return q;
      }


      /**
       * The TPS f(x) = sum_j w_j phi(|x - c_j|) + [1 x] a over the control
       * points c_j, with phi(r) = -r, the kernel of the 3D thin plate. With
       * w orthogonal to the affine functions at the control points (w = Q2
       * g, Q2 a basis of that complement), w^T Phi w = g^T Q2^T Phi Q2 g >= 0
       * is the bending energy int |D^2 f|^2 / (8 pi). Fitted by regularised
       * least squares to one goal position per source point. The design
       * matrix over the source points never changes: its Gram matrix is
       * formed once, and a fit costs two products with the design matrix and
       * a small solve (factorised once per temperature).
       */
      class ThinPlateSpline
      {
      public:
        ThinPlateSpline(const Eigen::MatrixX3d &points,
                        const Eigen::MatrixX3d &control)
        {
          const Eigen::Index n_control = control.rows();
          const Eigen::Index n_bending =
            std::max<Eigen::Index>(0, n_control - 4);
          n_unknowns = n_bending + 4;

          Eigen::MatrixXd affine_at_control(n_control, 4);
          affine_at_control.col(0).setOnes();
          affine_at_control.rightCols(3) = control;
          const Eigen::MatrixXd q2 =
            orthogonal_complement(affine_at_control).rightCols(n_bending);

          const auto kernel = [&](const Eigen::MatrixX3d &at) {
            Eigen::MatrixXd values(at.rows(), n_control);
            for (Eigen::Index j = 0; j < n_control; ++j)
              values.col(j) = -(at.rowwise() - control.row(j)).rowwise().norm();
            return values;
          };
          bending = q2.transpose() * kernel(control) * q2;

          // In blocks of rows: no N x K kernel matrix besides the design.
          const Eigen::Index n     = points.rows();
          const Eigen::Index block = 1024;
          design.resize(n, n_unknowns);
          for (Eigen::Index start = 0; start < n; start += block)
            {
              const Eigen::Index rows = std::min(block, n - start);
              design.block(start, 0, rows, n_bending) =
                kernel(points.middleRows(start, rows)) * q2;
            }
          design.col(n_bending).setOnes();
          design.rightCols(3) = points;

          // The data term is the mean squared misfit, so that lambda does
          // not depend on the number of points.
          gram.setZero(n_unknowns, n_unknowns);
          gram.selfadjointView<Eigen::Lower>().rankUpdate(design.transpose(),
                                                          1. / n);
          coefficients.setZero(n_unknowns, 3);
          coefficients.bottomRows(3).setIdentity();
        }

        /// Fit to @p goal (one row per source point) with weight @p lambda
        /// on the bending energy and @p affine_lambda on |A - I|^2.
        void
        fit(const Eigen::MatrixX3d &goal,
            const double            lambda,
            const double            affine_lambda)
        {
          if (lambda != factorised_lambda ||
              affine_lambda != factorised_affine_lambda)
            factorise(lambda, affine_lambda);
          Eigen::MatrixX3d rhs =
            design.transpose() * goal / static_cast<double>(design.rows());
          rhs.bottomRows(3) += affine_lambda * Eigen::Matrix3d::Identity();
          coefficients = factorisation.solve(rhs);
        }

        /// The source points moved by the current fit.
        Eigen::MatrixX3d
        warped() const
        {
          return design * coefficients;
        }

      private:
        void
        factorise(const double lambda, const double affine_lambda)
        {
          const Eigen::Index n_bending = n_unknowns - 4;
          Eigen::MatrixXd    matrix    = gram;
          matrix.topLeftCorner(n_bending, n_bending) += lambda * bending;
          matrix.bottomRightCorner(3, 3).diagonal().array() += affine_lambda;
          // A ridge relative to the diagonal keeps degenerate input
          // (coplanar points, no affine weight) solvable.
          matrix.diagonal().array() += 1e-12 * matrix.diagonal().mean();
          factorisation.compute(matrix);
          if (factorisation.info() != Eigen::Success)
            throw Error("TPS-RPM: the thin-plate spline system is singular; "
                        "raise lambda or the affine weight.");
          factorised_lambda        = lambda;
          factorised_affine_lambda = affine_lambda;
        }

        Eigen::Index                 n_unknowns = 0;
        Eigen::MatrixXd              bending;
        Eigen::MatrixXd              design;
        Eigen::MatrixXd              gram;
        Eigen::LDLT<Eigen::MatrixXd> factorisation;
        double factorised_lambda = std::numeric_limits<double>::quiet_NaN();
        double factorised_affine_lambda =
          std::numeric_limits<double>::quiet_NaN();
        Eigen::MatrixX3d coefficients;
      };


      /**
       * The sparse match matrix: row a holds the target points within the
       * search radius of warped source point a. Softassign makes it doubly
       * stochastic with an outlier row and column of constant entry w (Chui
       * and Rangarajan): m_aj = u_a g_aj v_j with g_aj = exp(-d^2 / (2T)),
       * every row (outlier column included) and every column (outlier row
       * included) summing to 1; the outlier row and column themselves are
       * not normalised.
       */
      class MatchMatrix
      {
      public:
        explicit MatchMatrix(const Eigen::Index n_target)
            : column_scale(Eigen::VectorXd::Ones(n_target))
        {}

        void
        softassign(const KdTree           &tree,
                   const Eigen::MatrixX3d &warped,
                   const double            temperature,
                   const TpsRpmParameters &p)
        {
          const Eigen::Index n = warped.rows();
          row_start.assign(1, 0);
          column.clear();
          entry.clear();
          Neighbours   neighbours(p.search_radius * p.search_radius *
                                temperature);
          const double half_inverse_temperature = 0.5 / temperature;
          for (Eigen::Index a = 0; a < n; ++a)
            {
              const double query[3] = {warped(a, 0),
                                       warped(a, 1),
                                       warped(a, 2)};
              neighbours.found.clear();
              tree.radiusSearchCustomCallback(query, neighbours);
              for (const auto &[j, squared_distance] : neighbours.found)
                {
                  column.push_back(j);
                  entry.push_back(
                    std::exp(-squared_distance * half_inverse_temperature));
                }
              row_start.push_back(column.size());
            }

          // Alternate row and column normalisation until the rows are
          // within the tolerance (the columns are exact after each sweep).
          // The column scales start from the previous softassign's: they
          // change slowly.
          const double    w = p.outlier_weight;
          Eigen::VectorXd row_scale(n);
          Eigen::VectorXd column_sum(column_scale.size());
          for (unsigned int sweep = 0; sweep < p.sinkhorn_iterations; ++sweep)
            {
              double worst = 0.;
              for (Eigen::Index a = 0; a < n; ++a)
                {
                  double sum = w;
                  for (std::size_t e = row_start[a]; e < row_start[a + 1]; ++e)
                    sum += entry[e] * column_scale[column[e]];
                  if (sweep > 0)
                    worst = std::max(worst, std::abs(row_scale[a] * sum - 1.));
                  row_scale[a] = 1. / sum;
                }
              if (sweep > 0 && worst < p.sinkhorn_tolerance)
                break;
              column_sum.setConstant(w);
              for (Eigen::Index a = 0; a < n; ++a)
                for (std::size_t e = row_start[a]; e < row_start[a + 1]; ++e)
                  column_sum[column[e]] += row_scale[a] * entry[e];
              column_scale = column_sum.cwiseInverse();
            }

          inlier_mass.resize(n);
          for (Eigen::Index a = 0; a < n; ++a)
            {
              double mass = 0.;
              for (std::size_t e = row_start[a]; e < row_start[a + 1]; ++e)
                {
                  entry[e] *= row_scale[a] * column_scale[column[e]];
                  mass += entry[e];
                }
              inlier_mass[a] = mass;
            }
        }

        /// For each row a: sum over j of m_aj target_j.
        Eigen::MatrixX3d
        weighted_targets(const Eigen::MatrixX3d &target) const
        {
          Eigen::MatrixX3d sum = Eigen::MatrixX3d::Zero(inlier_mass.size(), 3);
          for (Eigen::Index a = 0; a < sum.rows(); ++a)
            for (std::size_t e = row_start[a]; e < row_start[a + 1]; ++e)
              sum.row(a) += entry[e] * target.row(column[e]);
          return sum;
        }

        /// Row sums over the target columns (the outlier column left out).
        Eigen::VectorXd inlier_mass;

      private:
        std::vector<std::size_t>  row_start;
        std::vector<unsigned int> column;
        std::vector<double>       entry;
        Eigen::VectorXd           column_scale;
      };
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
    tps_rpm(const Eigen::MatrixX3d &source_in,
            const Eigen::MatrixX3d &target_in,
            const TpsRpmParameters &p)
    {
      check_points(source_in, "source");
      check_points(target_in, "target");
      check_parameters(p);

      // About the source's centroid: the affine columns of the TPS are then
      // well conditioned, and its identity is A = I with no translation.
      const Eigen::RowVector3d centroid = source_in.colwise().mean();
      const Eigen::MatrixX3d   source   = source_in.rowwise() - centroid;
      const Eigen::MatrixX3d   target   = target_in.rowwise() - centroid;
      const Eigen::Index       n        = source.rows();

      const double t_final   = p.final_temperature;
      double       t_initial = p.initial_temperature;
      if (t_initial <= 0.)
        {
          const double rms = std::sqrt(source.rowwise().squaredNorm().mean());
          t_initial        = std::max(std::pow(0.2 * rms, 2), t_final);
        }

      const std::vector<unsigned int> control_rows =
        subsample(source, p.control_points);
      Eigen::MatrixX3d control(control_rows.size(), 3);
      for (std::size_t k = 0; k < control_rows.size(); ++k)
        control.row(k) = source.row(control_rows[k]);
      ThinPlateSpline tps(source, control);

      const Cloud cloud{target};
      KdTree      tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
      tree.buildIndex();
      MatchMatrix match(target.rows());

      TpsRpmResult     result;
      Eigen::MatrixX3d warped = source;
      double           t      = t_initial;
      while (true)
        {
          const double lambda =
            annealed(p.lambda_initial, p.lambda_final, t, t_initial, t_final);
          const double affine_lambda = annealed(p.affine_lambda_initial,
                                                p.affine_lambda_final,
                                                t,
                                                t_initial,
                                                t_final);
          for (unsigned int i = 0; i < p.iterations_per_temperature; ++i)
            {
              match.softassign(tree, warped, t, p);
              // A point pulls on the TPS with its inlier mass r_a: its goal
              // is r_a times its matches' mean plus 1 - r_a times its own
              // position (one step towards the weighted fit, which keeps the
              // system matrix fixed). An outlier stays where the TPS of the
              // others takes it.
              Eigen::MatrixX3d goal = match.weighted_targets(target);
              for (Eigen::Index a = 0; a < n; ++a)
                {
                  // An unconverged softassign may leave r_a above 1.
                  const double mass = match.inlier_mass[a];
                  if (mass > 1.)
                    goal.row(a) /= mass;
                  else
                    goal.row(a) += (1. - mass) * warped.row(a);
                }
              tps.fit(goal, lambda, affine_lambda);
              warped = tps.warped();
              ++result.iterations;
            }
          if (t <= t_final)
            break;
          t = std::max(t * p.annealing_rate, t_final);
        }

      // The match weights for the final TPS; each point's correspondence is
      // the target point closest to where the TPS takes it.
      match.softassign(tree, warped, t, p);
      result.correspondence.resize(n, 3);
      for (Eigen::Index a = 0; a < n; ++a)
        result.correspondence.row(a) =
          target_in.row(closest(tree, warped.row(a)));
      result.warped_source = warped.rowwise() + centroid;
      result.distance = (result.correspondence - source_in).rowwise().norm();
      result.match_weight      = match.inlier_mass.cwiseMin(1.);
      result.final_temperature = t;
      return result;
    }
  } // namespace Validation
} // namespace softface

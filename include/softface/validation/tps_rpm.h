#ifndef softface_validation_tps_rpm_h
#define softface_validation_tps_rpm_h

#include <Eigen/Dense>

#include <vector>

namespace softface
{
  /**
   * How far a predicted skin is from the post-operative one (seed 3.5.1).
   */
  namespace Validation
  {
    /**
     * The knobs of tps_rpm(). Lengths are in mm; a temperature T is the
     * variance (mm^2) of the Gaussian exp(-d^2 / (2 T)) that weighs a
     * candidate match at distance d.
     */
    struct TpsRpmParameters
    {
      /// T at the start (mm^2); <= 0: automatic, (0.2 r)^2 with r the RMS
      /// distance of the source points from their centroid (about 8 mm on
      /// a 60 x 80 x 100 mm ellipsoid, 11 mm on a face): the first matches
      /// then reach beyond displacements of several mm.
      double initial_temperature = 0.;
      /// T at the end (mm^2, > 0), well below the squared point spacing, so
      /// that each source point ends matched to one target point.
      double final_temperature = 0.01;
      /// T is multiplied by this after each temperature's iterations, in
      /// (0, 1).
      double annealing_rate = 0.9;
      /// Softassign + TPS iterations at each temperature (>= 1).
      unsigned int iterations_per_temperature = 3;
      /// Weight (mm) of the TPS bending energy at the initial temperature,
      /// relative to the mean squared misfit (mm^2); annealed geometrically
      /// with T down to lambda_final.
      double lambda_initial = 100.;
      /// Weight (mm) of the TPS bending energy at the final temperature.
      double lambda_final = 0.01;
      /// Weight (mm^2) of |A - I|^2, A the linear part of the TPS, at the
      /// initial temperature; annealed like lambda. Keeps the early, blurred
      /// matches from shrinking or turning the source, and skin that the
      /// target lacks from dragging the rest along.
      double affine_lambda_initial = 100.;
      /// Weight (mm^2) of |A - I|^2 at the final temperature. Not much
      /// smaller: with none, two samplings of one surface slide (turn) the
      /// source along it.
      double affine_lambda_final = 1.;
      /// The TPS has at most this many control points (>= 1), a farthest-
      /// point subsample of the source, so that a fit is a small dense
      /// solve; fewer than 5 leave an affine map.
      unsigned int control_points = 300;
      /// Entry of the outlier row and column of the match matrix, next to
      /// the entries exp(-d^2 / (2 T)), in (0, 1]: a point farther than
      /// sqrt(-2 T ln w) from every point of the other set ends an outlier
      /// (the default exp(-4.5): 3 sqrt(T)).
      double outlier_weight = 0.011108996538242306;
      /// Candidate matches are the target points within this many sqrt(T)
      /// of a warped source point (> 0): the match matrix is sparse.
      double search_radius = 3.5;
      /// At most this many row/column normalisation sweeps per softassign
      /// (>= 1).
      unsigned int sinkhorn_iterations = 30;
      /// Softassign stops when every row sum is within this of 1 (> 0; the
      /// column sums are 1 after each sweep).
      double sinkhorn_tolerance = 0.01;
    };

    /// What tps_rpm() found.
    struct TpsRpmResult
    {
      /// The source points moved by the final TPS.
      Eigen::MatrixX3d warped_source;
      /// For each source point, its corresponding target point: the target
      /// point closest to its warped position (warped_source) at the end.
      /// Meaningful where match_weight is near 1.
      Eigen::MatrixX3d correspondence;
      /// |source_i - correspondence_i| (mm).
      Eigen::VectorXd distance;
      /// Each source point's inlier mass in the final match matrix, in [0,
      /// 1]: near 1 matched, near 0 an outlier (no target point within
      /// about 3 sqrt(final T) of its warped position, e.g. skin that the
      /// other scan does not cover). Where the target samples the surface
      /// at other points than the source, most points end near 0 at a small
      /// final temperature: then it does not tell outliers.
      Eigen::VectorXd match_weight;
      /// Total softassign + TPS iterations (TPS fits).
      unsigned int iterations = 0;
      /// The temperature of the last iteration (mm^2).
      double final_temperature = 0.;
    };

    /**
     * Non-rigid correspondences from @p source to @p target (one point a
     * row, mm) by TPS-RPM (Chui and Rangarajan 2000, 2003): deterministic
     * annealing of a softassign match matrix with an outlier row and
     * column, alternating with a thin-plate spline fit of the source to
     * its matches. The variant for large surfaces (Mollemans et al. 2007
     * used one): the match matrix only holds target points within
     * search_radius sqrt(T) of each warped source point; the TPS is a
     * regularised least-squares fit over all source points with a
     * subsample of them as control points; a point's pull on the TPS is
     * its inlier mass. Memory: the N x control_points design matrix of the
     * TPS and the sparse match matrix.
     *
     * Where the target is the same points moved, the correspondences are
     * recovered exactly. Where it samples the surface at other points, the
     * motion along the surface is barely in the data (only in the point
     * density): the correspondences then lie on the right surface but may
     * be some mm off along it.
     *
     * Deterministic. Throws an Error on empty or non-finite points and on
     * nonsense parameters.
     */
    TpsRpmResult
    tps_rpm(const Eigen::MatrixX3d &source,
            const Eigen::MatrixX3d &target,
            const TpsRpmParameters &parameters = TpsRpmParameters());

    /**
     * At most @p n of @p points, well spread: farthest-point sampling from
     * the point farthest from the centroid (ties: the lowest index).
     * Deterministic; all rows when @p n >= their number, fewer than @p n
     * when the rest coincide with chosen points. Returns row indices in
     * ascending order. Throws an Error on no points or n = 0.
     */
    std::vector<unsigned int>
    subsample(const Eigen::MatrixX3d &points, unsigned int n);
  } // namespace Validation
} // namespace softface

#endif

#ifndef softface_validation_tps_rpm_h
#define softface_validation_tps_rpm_h

#include <softface/mapping/triangle_search.h>

#include <Eigen/Dense>

#include <vector>

namespace softface
{
  /**
   * How far a predicted skin is from the post-operative one (Mollemans et al.
   * 2007, Sec. 3.5.1).
   */
  namespace Validation
  {
    /**
     * The knobs of tps_rpm(). Lengths in mm; a temperature T is the variance
     * (mm^2) of the Gaussian exp(-d^2 / (2 T)) that weighs a point's match
     * at distance d against the outlier class.
     */
    struct TpsRpmParameters
    {
      /// T at the start (mm^2); <= 0: automatic, (0.2 r)^2 with r the RMS
      /// distance of the source points from their centroid (about 11 mm on
      /// a face): the first fits are stiff and reach far.
      double initial_temperature = 0.;
      /// T at the end (mm^2, > 0): a point farther than about 3 sqrt(T)
      /// from the target after the warp ends an outlier.
      double final_temperature = 0.01;
      /// T is multiplied by this after each temperature's iterations, in
      /// (0, 1).
      double annealing_rate = 0.8;
      /// Match + spline iterations at each temperature (>= 1).
      unsigned int iterations_per_temperature = 2;
      /// Weight (mm) of the spline's bending energy at the initial
      /// temperature, relative to the mean squared misfit (mm^2); annealed
      /// geometrically with T down to lambda_final.
      double lambda_initial = 100.;
      /// Weight (mm) of the bending energy at the final temperature.
      double lambda_final = 0.01;
      /// Spline centres (>= 1): a farthest-point subsample of the fitted
      /// points; fewer than 5 leave an affine map.
      unsigned int control_points = 300;
      /// The spline is fitted to at most this many source points (>= 1), a
      /// fixed pseudo-random subset; every source point is then warped by
      /// it and matched.
      unsigned int fit_points = 10000;
      /// The outlier class's weight next to exp(-d^2 / (2 T)), in (0, 1]
      /// (default exp(-4.5): an outlier beyond 3 sqrt(T)).
      double outlier_weight = 0.011108996538242306;
    };

    /// What tps_rpm() found, one row per source point.
    struct TpsRpmResult
    {
      /// The source points moved by the final spline.
      Eigen::MatrixX3d warped_source;
      /// The point of the target surface closest to the warped source
      /// point: the source point's corresponding point.
      Eigen::MatrixX3d correspondence;
      /// |source - correspondence| (mm).
      Eigen::VectorXd distance;
      /// g / (g + w) with g = exp(-d^2 / (2 T)), d = |warped -
      /// correspondence|, at the final temperature: near 1 for a point
      /// matched, near 0 for an outlier (no counterpart on the target); 0
      /// where the correspondence lies on the target's rim (an edge of one
      /// triangle only: the surface ends there).
      Eigen::VectorXd match_weight;
      /// Whether the correspondence lies on the target's rim: the point has
      /// no counterpart on the target (which ends there).
      std::vector<bool> beyond_rim;
      unsigned int      iterations        = 0;
      unsigned int      n_fit_points      = 0;
      unsigned int      n_control_points  = 0;
      double            final_temperature = 0.;
    };

    /**
     * Corresponding points of a point set on a continuous surface by the
     * variant of TPS-RPM (Chui and Rangarajan 2003) that Mollemans et al.
     * 2007 (3.5.1) used after Tondeur et al.: every source point (a
     * predicted skin's) is matched to the target surface (the post-operative
     * skin's triangles), not to its vertices. A thin-plate spline warps the
     * source towards the target by deterministic annealing: at temperature
     * T each fitted point's goal is its closest point on the target,
     * weighted against an outlier class by exp(-d^2 / (2 T)) (the softassign
     * over a continuous surface, at its zero-width limit), while the
     * spline's bending weight falls with T. A point whose closest point
     * lies on the target's rim (where an open surface ends) does not pull.
     * The spline, stiff at first,
     * carries motion along the surface, which closest points cannot see,
     * from where the surface has shape; at the end every source point is
     * warped and matched to its closest target point.
     *
     * The skins must be registered (no rigid motion between them): motion
     * along a smooth surface is found only as far as the spline carries it.
     * Two samplings of one surface match to the surface's own distance
     * (chords of its triangles); under a known smooth warp the percentiles
     * of the distances come close to the exact ones, the partners point by
     * point less so (tests/validation_tps_rpm.cc, doc/skin.md).
     *
     * Costs: a closest-point query (an R-tree of the target's triangles)
     * per fitted point per iteration, on Threads::n_threads() threads; the
     * spline's fit_points x (control_points + 4) design matrix; at the end
     * one spline evaluation and one query per source point. Deterministic
     * on any number of threads. Throws an Error on empty or non-finite
     * points, a target without triangles and nonsense parameters.
     */
    TpsRpmResult
    tps_rpm(const Eigen::MatrixX3d        &source,
            const SurfaceMapping::Surface &target,
            const TpsRpmParameters        &parameters = TpsRpmParameters());

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

#ifndef softface_validation_distances_h
#define softface_validation_distances_h

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/point.h>

#include <softface/mapping/triangle_search.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * How far a predicted skin is from the post-operative one (Mollemans et al.
   * 2007, Sec. 3.5.1): distances and their statistics over the points that no
   * mask removes.
   */
  namespace Validation
  {
    /**
     * The signed distance of every point of @p points to the surface @p to:
     * the distance to its closest point there, negative where the point
     * lies behind @p to (against its outward normal, interpolated from the
     * point normals at the closest point), as in the paper's Fig. 10.
     */
    std::vector<double>
    signed_distances(const std::vector<Point<3>>   &points,
                     const SurfaceMapping::Surface &to);

    /// The same for points one at a time, the surface's search tree and
    /// normals built once (softface serve measures every re-plan).
    class SignedDistance
    {
    public:
      /// Keeps a reference to @p to.
      explicit SignedDistance(const SurfaceMapping::Surface &to);
      double
      operator()(const Point<3> &point) const;

    private:
      const SurfaceMapping::Surface       &to;
      const SurfaceMapping::TriangleSearch search;
      const std::vector<Tensor<1, 3>>      normals;
    };

    /// Regions left out of the statistics (the paper left out the eyes, the
    /// neck): axis-aligned boxes.
    struct Mask
    {
      std::vector<BoundingBox<3>> boxes;

      /// "x0, y0, z0; x1, y1, z1" boxes separated by '|'; empty: no mask.
      /// Throws an Error naming @p parameter on a malformed value.
      static Mask
      parse(const std::string &text, const std::string &parameter);

      bool
      masked(const Point<3> &p) const;
    };

    /// What the paper reports of a distance map (mm).
    struct Statistics
    {
      unsigned int n             = 0;
      double       mean          = 0.; ///< of the signed distances
      double       mean_absolute = 0.;
      double       variance      = 0.; ///< of the signed distances
      double       max_absolute  = 0.;
      double       p50 = 0., p90 = 0., p95 = 0.; ///< percentiles of |d|
    };

    /**
     * The q-th percentile (0..100) of @p values by linear interpolation
     * between the order statistics (position q/100 (n-1); numpy's default).
     */
    double
    percentile(std::vector<double> values, const double q);

    /**
     * Statistics of @p distances at the points that @p mask does not remove
     * and, if @p in_region is not empty, where it is true (the skin the
     * mesh reaches: outside it nothing was simulated). Throws an Error if no
     * point is left.
     */
    Statistics
    statistics(const std::vector<double>   &distances,
               const std::vector<Point<3>> &points,
               const Mask                  &mask,
               const std::vector<bool>     &in_region = {});
  } // namespace Validation
} // namespace softface

#endif

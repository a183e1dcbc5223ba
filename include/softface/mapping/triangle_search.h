#ifndef softface_mapping_triangle_search_h
#define softface_mapping_triangle_search_h

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/numerics/rtree.h>

#include <array>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace SurfaceMapping
  {
    /// A triangulated surface: points and triangles (indices into points).
    struct Surface
    {
      std::vector<Point<3>>                    points;
      std::vector<std::array<unsigned int, 3>> triangles;
    };

    /// The point of triangle @p t closest to @p p, and its barycentric
    /// coordinates (weights of t[0], t[1], t[2]).
    std::pair<Point<3>, std::array<double, 3>>
    closest_point_on_triangle(const Point<3>                &p,
                              const std::array<Point<3>, 3> &t);

    /**
     * Closest points on a triangle surface (the skin surface of the mesh for
     * the shape-function mapping, the post-operative skin for the
     * distances): an R-tree of the triangles' bounding boxes (Boost.Geometry
     * through deal.II), searched nearest box first until no box can hold a
     * closer point.
     */
    class TriangleSearch
    {
    public:
      explicit TriangleSearch(const Surface &surface);

      struct Hit
      {
        unsigned int          triangle = 0;
        Point<3>              point;
        std::array<double, 3> barycentric{{0., 0., 0.}};
        double                distance = 0.;
      };

      /// The closest point of the surface to @p p.
      Hit
      closest(const Point<3> &p) const;

    private:
      const Surface &surface;
      using Box = std::pair<BoundingBox<3>, unsigned int>;
      RTree<Box> tree;
    };

    /**
     * Unit normals at the points of @p surface (area-weighted means of the
     * triangles' normals), oriented by the triangles' winding; a closed
     * surface wound inwards (negative enclosed volume) is turned outwards.
     */
    std::vector<Tensor<1, 3>>
    point_normals(const Surface &surface);

    /**
     * Throws an Error naming @p what and the first edge shared by more than
     * two triangles, a triangle that repeats a point or names a point past
     * the end: the mappings and distances need a manifold surface.
     */
    void
    check_manifold(const Surface &surface, const std::string &what);
  } // namespace SurfaceMapping
} // namespace softface

#endif

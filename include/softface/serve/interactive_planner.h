#ifndef softface_serve_interactive_planner_h
#define softface_serve_interactive_planner_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <softface/mapping/triangle_search.h>
#include <softface/models/response_basis.h>
#include <softface/serve/parameters.h>
#include <softface/simulator/simulator.h>
#include <softface/validation/distances.h>

#include <array>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Serve
  {
    /**
     * A scene ready for interactive planning: the scene and its skin (the
     * dense skin when it has one, else the mesh's outer surface), and for
     * each offered model its response basis, so that a plan (a motion per
     * moved segment) becomes the skin's displacement in milliseconds.
     */
    class InteractivePlanner
    {
    public:
      /// A moved segment's motion as the page's sliders give it: a
      /// translation (mm), then rotations about the x, y and z axes
      /// (degrees, applied in that order) through the segment's centre.
      using Motion = std::array<double, 6>;

      struct Segment
      {
        std::string name;
        Point<3>    centre; ///< the join points' centroid
      };

      struct Result
      {
        /// Three per moving point (moving_points()).
        std::vector<float> displacement;
        /// With a distance asked for: the signed distance (mm) of each
        /// moving point, displaced, to the post-operative skin.
        std::vector<float> distance;
        double             combination_ms = 0.;
        double             mapping_ms     = 0.;
        double             distance_ms    = 0.;
      };

      /// Prepare @p scene_file (Simulator::prepare), set up every model of
      /// Serve/Models and build its basis; progress on @p out.
      InteractivePlanner(const std::string &scene_file, std::ostream &out);
      ~InteractivePlanner();

      const Parameters &
      parameters() const;
      const std::vector<Segment> &
      moved_segments() const;
      std::vector<std::string>
      model_names() const;
      /// The surface shown, at rest.
      const SurfaceMapping::Surface &
      surface() const;
      /// The post-operative skin (empty without one).
      const SurfaceMapping::Surface &
      post_operative() const;
      /// The surface points a plan can move, in increasing order (skin
      /// points the mesh reaches; mesh surface points not held by a fixed
      /// segment): a re-plan sends only theirs.
      const std::vector<unsigned int> &
      moving_points() const;
      /// The signed distance (mm) of every surface point at rest to the
      /// post-operative skin (empty without one).
      const std::vector<float> &
      rest_distances() const;
      /// "dense skin" or "mesh surface".
      const std::string &
      surface_kind() const;

      /**
       * The surface's displacement under @p motions (one per moved segment,
       * in moved_segments()' order) by @p model. Throws an Error for an
       * unknown model, a wrong number of motions, a value that is not finite
       * or past the limits. With @p with_distance (and a post-operative
       * skin) also the moving points' distances to it.
       */
      Result
      replan(const std::string         &model,
             const std::vector<Motion> &motions,
             const bool                 with_distance = false) const;

    private:
      /// The distance to the post-operative skin of point(k) for every k
      /// below distance.size(), into distance[k].
      void
      distances(const std::function<Point<3>(unsigned int)> &point,
                std::vector<float>                          &distance) const;

      Simulator                                           simulator;
      Parameters                                          serve_parameters;
      std::vector<Segment>                                segments;
      std::vector<unsigned int>                           segment_indices;
      std::vector<std::string>                            names;
      std::vector<std::unique_ptr<Models::ResponseBasis>> bases;
      SurfaceMapping::Surface                             shown;
      SurfaceMapping::Surface                             post;
      std::string                                         kind;
      std::vector<unsigned int>                           moving;
      std::unique_ptr<Validation::SignedDistance>         distance_to_post;
      std::vector<float>                                  rest_distance;
      /// Mesh surface: the triangulation vertex of each surface point.
      std::vector<unsigned int> mesh_vertex_of_point;
    };
  } // namespace Serve
} // namespace softface

#endif

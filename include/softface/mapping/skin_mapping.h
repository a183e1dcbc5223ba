#ifndef softface_mapping_skin_mapping_h
#define softface_mapping_skin_mapping_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <softface/mapping/triangle_search.h>

#include <array>
#include <set>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Volume/surface mapping (Mollemans et al. 2007, Sec. 3.4): the displacement
   * computed on the coarse tetrahedral mesh carried to the dense skin surface
   * made from the CT. Both of the paper's methods are an initialisation (step
   * A) that fixes, for every skin point, weights of mesh vertices, and an
   * update (step B, on every prediction) that sums the weighted vertex
   * displacements: a sparse matrix times a vector.
   */
  namespace SurfaceMapping
  {
    /// What the mappings need of the tetrahedral mesh.
    struct VolumeMesh
    {
      /// Every vertex of the triangulation (by its index there).
      std::vector<Point<3>>                    vertices;
      std::vector<std::array<unsigned int, 4>> cells;
      /// The faces of the mesh's skin: boundary faces with one of the
      /// boundary ids asked for (every boundary face if none); the points
      /// are the vertices above.
      Surface                   skin;
      std::vector<unsigned int> cell_of_skin_triangle;

      /// The mesh of @p triangulation; @p skin_boundary_ids empty: every
      /// boundary face is skin.
      static VolumeMesh
      from_triangulation(const Triangulation<3>             &triangulation,
                         const std::set<types::boundary_id> &skin_boundary_ids);
    };

    /// The two methods of the paper.
    enum class Method
    {
      shape_functions,
      inverse_distance
    };

    /// "shape functions" or "inverse distance"; anything else is an Error.
    Method
    method_from_name(const std::string &name);
    std::string
    name_of(const Method method);

    struct Parameters
    {
      Method method = Method::shape_functions;
      /// Skin points farther than this from the mesh's skin (mm) are outside
      /// the simulated region (the mesh covers the face only): they stay.
      double reach = 3.;
      /// Inverse distance weighting: known points within this radius (mm,
      /// the paper's x) ...
      double radius = 3.;
      /// ... and fewer than this many connectivity rings away (the paper's y).
      unsigned int rings = 5;
    };

    /**
     * Step B of both methods: skin point i moves by
     * sum_k weights[k] u(vertices[k]) over k in [row_start[i], row_start[i+1]).
     * A point outside the mesh's reach has no weights and stays.
     */
    class SkinMapping
    {
    public:
      /// @p vertex_displacement by triangulation vertex index.
      void
      map(const std::vector<Tensor<1, 3>> &vertex_displacement,
          std::vector<Tensor<1, 3>>       &skin_displacement) const;

      unsigned int
      n_points() const
      {
        return row_start.size() - 1;
      }

      /// Skin points farther than the reach from the mesh: they stay.
      unsigned int n_outside = 0;
      /// Inverse distance weighting: points within the reach that found no
      /// known point within the radius and rings (they stay too; a warning
      /// tells the user to widen the radius or the rings).
      unsigned int n_without_neighbours = 0;
      /// Skin points inside a tetrahedron (the rest project onto the skin).
      unsigned int n_inside = 0;

      /// Whether each skin point is within the reach of the mesh (the
      /// simulated region); distances are measured only there.
      std::vector<bool> in_reach;

      std::vector<unsigned int> row_start = {0};
      std::vector<unsigned int> vertices;
      std::vector<double>       weights;

      /// Wall seconds of step A's parts, in their order (what the paper's
      /// Table 4 times as one figure): for shape functions the tetrahedra's
      /// R-tree, the containing tetrahedra, and the points outside the mesh
      /// projected onto its skin; for inverse distances the skin points'
      /// R-tree, matching the mesh's skin vertices, the skin's edges, the
      /// reach of each unmatched point, and the rings.
      std::vector<std::pair<std::string, double>> step_a_parts;
    };

    /**
     * Step A of the shape-function method: each skin point gets the
     * tetrahedron that contains it, or else the one whose skin face it
     * projects onto (the closest point of the mesh's skin), and the P1 shape
     * functions of that tetrahedron at the point (the paper's eq. 13; outside
     * the tetrahedron they extrapolate linearly).
     */
    SkinMapping
    shape_function_mapping(const VolumeMesh &mesh,
                           const Surface    &skin_surface,
                           const Parameters &parameters);

    /**
     * Step A of inverse distance weighting: every vertex of the mesh's skin
     * is matched to its closest skin point (the "known" points); each skin
     * point then takes the known points within the radius and fewer than
     * the rings away along the skin's edges, weighted by 1/distance (the
     * paper's eq. 14); a known point is its own answer. A skin point matched by
     * several mesh vertices takes their mean.
     */
    SkinMapping
    inverse_distance_mapping(const VolumeMesh &mesh,
                             const Surface    &skin_surface,
                             const Parameters &parameters);

    /// Step A by @p parameters.method. Throws an Error if no skin point is
    /// within the reach of the mesh (a skin in another frame or of another
    /// patient).
    SkinMapping
    initialise(const VolumeMesh &mesh,
               const Surface    &skin_surface,
               const Parameters &parameters);
  } // namespace SurfaceMapping
} // namespace softface

#endif

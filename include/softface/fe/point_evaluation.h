#ifndef softface_point_evaluation_h
#define softface_point_evaluation_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Displacements at arbitrary points of the reference configuration, for
   * comparing solutions on different meshes and of different degree (the
   * accuracy benchmark evaluates every run at the vertices of its coarsest
   * mesh). The tetrahedra are affine, so a point's reference coordinates in
   * its cell are its barycentric coordinates; any FE field on the mesh is
   * then evaluated with its shape functions there.
   */
  class PointEvaluation
  {
  public:
    /**
     * Find the cell of every point (R-tree of cell bounding boxes). A point
     * on a face or edge takes any cell that contains it. Throws an Error
     * naming the first point that lies outside the mesh by more than
     * @p tolerance (relative to the cell size).
     */
    PointEvaluation(const Triangulation<3>      &triangulation,
                    const std::vector<Point<3>> &points,
                    const double                 tolerance = 1e-8);

    /// The vector field (three components) @p u on @p dof_handler.
    std::vector<Tensor<1, 3>>
    evaluate(const DoFHandler<3> &dof_handler, const Vector<double> &u) const;

    const std::vector<Point<3>> &
    points() const;

    /// The active cell index of each point's cell.
    std::vector<unsigned int>
    cell_indices() const;

    /// Each point's coordinates in its cell's reference cell.
    const std::vector<Point<3>> &
    reference_coordinates() const;

  private:
    std::vector<Point<3>>                               evaluation_points;
    std::vector<Triangulation<3>::active_cell_iterator> cells;
    std::vector<Point<3>>                               reference_points;
  };

} // namespace softface

#endif

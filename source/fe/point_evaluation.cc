// Displacements at arbitrary points (fe): the cell and reference coordinates
// of every point, found once, then any FE field on the mesh evaluated there
// by its shape functions (Output/Evaluation points, the accuracy benchmark).

#include <deal.II/base/bounding_box.h>
#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>
#include <deal.II/numerics/rtree.h>

#include <softface/core/error.h>
#include <softface/core/tetrahedron.h>
#include <softface/fe/point_evaluation.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace softface
{
  namespace
  {
    double
    smallest_barycentric(const Point<3> &xi)
    {
      return std::min({1. - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]});
    }
  } // namespace

  PointEvaluation::PointEvaluation(const Triangulation<3>      &triangulation,
                                   const std::vector<Point<3>> &points,
                                   const double                 tolerance)
      : evaluation_points(points)
  {
    std::vector<std::pair<BoundingBox<3>, unsigned int>> boxes;
    std::vector<Triangulation<3>::active_cell_iterator>  all_cells;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        BoundingBox<3> box = cell->bounding_box();
        box.extend(tolerance * cell->diameter());
        boxes.emplace_back(box, all_cells.size());
        all_cells.push_back(cell);
      }
    const auto tree = pack_rtree(boxes);

    cells.reserve(points.size());
    reference_points.reserve(points.size());
    std::vector<std::pair<BoundingBox<3>, unsigned int>> candidates;
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        candidates.clear();
        tree.query(boost::geometry::index::intersects(points[i]),
                   std::back_inserter(candidates));
        double   best      = -std::numeric_limits<double>::max();
        unsigned best_cell = numbers::invalid_unsigned_int;
        Point<3> best_xi;
        for (const auto &candidate : candidates)
          {
            const Point<3> xi = Tetrahedron::reference_coordinates(
              Tetrahedron::vertices(all_cells[candidate.second]), points[i]);
            if (smallest_barycentric(xi) > best)
              {
                best      = smallest_barycentric(xi);
                best_cell = candidate.second;
                best_xi   = xi;
              }
          }
        if (best_cell == numbers::invalid_unsigned_int || best < -tolerance)
          {
            std::ostringstream m;
            m << "Evaluation point " << i + 1 << " (" << points[i]
              << ") lies outside the mesh.";
            throw Error(m.str());
          }
        // Clip the round-off of points on faces back into the cell.
        for (unsigned int d = 0; d < 3; ++d)
          best_xi[d] = std::max(best_xi[d], 0.);
        const double sum = best_xi[0] + best_xi[1] + best_xi[2];
        if (sum > 1.)
          best_xi /= sum;
        cells.push_back(all_cells[best_cell]);
        reference_points.push_back(best_xi);
      }
  }

  std::vector<Tensor<1, 3>>
  PointEvaluation::evaluate(const DoFHandler<3>  &dof_handler,
                            const Vector<double> &u) const
  {
    const FiniteElement<3> &fe = dof_handler.get_fe();
    AssertDimension(fe.n_components(), 3);
    AssertDimension(u.size(), dof_handler.n_dofs());
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    std::vector<Tensor<1, 3>>            values(cells.size());
    for (unsigned int p = 0; p < cells.size(); ++p)
      {
        const DoFHandler<3>::active_cell_iterator cell(
          &dof_handler.get_triangulation(),
          cells[p]->level(),
          cells[p]->index(),
          &dof_handler);
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < dofs.size(); ++i)
          values[p][fe.system_to_component_index(i).first] +=
            u[dofs[i]] * fe.shape_value(i, reference_points[p]);
      }
    return values;
  }

  const std::vector<Point<3>> &
  PointEvaluation::points() const
  {
    return evaluation_points;
  }

  std::vector<unsigned int>
  PointEvaluation::cell_indices() const
  {
    std::vector<unsigned int> indices;
    indices.reserve(cells.size());
    for (const auto &cell : cells)
      indices.push_back(cell->active_cell_index());
    return indices;
  }

  const std::vector<Point<3>> &
  PointEvaluation::reference_coordinates() const
  {
    return reference_points;
  }

} // namespace softface

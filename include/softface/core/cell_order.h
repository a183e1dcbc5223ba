#ifndef softface_cell_order_h
#define softface_cell_order_h

#include <deal.II/base/point.h>
#include <deal.II/grid/tria_description.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Mesh
  {
    /**
     * Sort items whose first point is below @p n_points: a counting sort by
     * that point, then each (small) bucket by operator<. The result is
     * std::sort's, in a few passes over memory instead of log n levels (the
     * 2M faces of a 491k-tetrahedron mesh: 0.35 s by std::sort). For lists
     * of cells or faces, whose points are spread over the mesh.
     */
    template <typename Item, typename FirstPoint>
    void
    sort_by_first_point(std::vector<Item> &items,
                        const std::size_t  n_points,
                        const FirstPoint  &first_point)
    {
      std::vector<std::size_t> start(n_points + 1, 0);
      for (const Item &item : items)
        ++start[first_point(item) + 1];
      std::partial_sum(start.begin(), start.end(), start.begin());
      std::vector<Item>        sorted(items.size());
      std::vector<std::size_t> next(start.begin(), start.end() - 1);
      for (Item &item : items)
        sorted[next[first_point(item)]++] = std::move(item);
      for (std::size_t p = 0; p < n_points; ++p)
        std::sort(sorted.begin() + start[p], sorted.begin() + start[p + 1]);
      items = std::move(sorted);
    }

    /**
     * The position of each point on a Hilbert curve through the points'
     * bounding box with @p bits bits per direction, packed into one integer:
     * the keys of deal.II's Utilities::inverse_Hilbert_space_filling_curve()
     * and pack_integers(), computed by the same transform without branches
     * on the bits, in pieces on the threads. @p bits is 1 to 21 (the packed
     * key has 64 bits).
     */
    std::vector<std::uint64_t>
    hilbert_keys(const std::vector<Point<3>> &points, int bits);

    /**
     * Put a mesh's cells in the order of a Hilbert curve through their
     * centres, number the vertices in the order the sorted cells first
     * touch them, then sort the cells by their vertex numbers. Neighbours in
     * space are then neighbours in memory: the degrees of freedom (numbered by
     * deal.II in cell order), the matrix rows, the mass tensor model's point
     * blocks. A gmsh mesh comes in the order its mesher made it, which
     * scatters each cell's vertices over the whole vertex array and makes
     * assembly six times slower than on a generated grid of the same size.
     * Every mesh softface's own readers read goes through this
     * (deal.II's serialised .vtu keeps its order); the generated cube is in
     * grid order already.
     *
     * The boundary faces in @p faces are renumbered with the vertices. The
     * result maps each new cell index to the cell's index in @p cells on
     * entry, so messages can still name a cell as its file did.
     */
    std::vector<unsigned int>
    order_for_locality(std::vector<Point<3>>    &vertices,
                       std::vector<CellData<3>> &cells,
                       SubCellData              &faces);
  } // namespace Mesh
} // namespace softface

#endif

#ifndef softface_cell_order_h
#define softface_cell_order_h

#include <deal.II/base/point.h>
#include <deal.II/grid/tria_description.h>

#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Mesh
  {
    /**
     * Put a mesh's cells in the order of a Hilbert curve through their
     * centres, number the vertices in the order the sorted cells first
     * touch them, then sort the cells by their vertex numbers. Neighbours in
     * space are then neighbours in memory: the degrees of freedom (numbered by
     * deal.II in cell order), the matrix rows, the mass tensor model's point
     * blocks. A gmsh mesh comes in the order its mesher made it, which
     * scattered each cell's vertices over the whole vertex array and made
     * assembly six times slower than on a generated grid of the same size
     * (issue 16). Every mesh softface's own readers read goes through this
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

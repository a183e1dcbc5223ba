#ifndef softface_io_mesh_data_h
#define softface_io_mesh_data_h

#include <deal.II/grid/tria.h>

#include <softface/core/mesh.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Mesh
  {
    /**
     * A tetrahedral mesh as a reader found it, before deal.II sees it:
     * points, tetrahedra (material ids) and boundary triangles (boundary
     * ids), each element with its number and line in the file for
     * messages.
     */
    struct MeshData
    {
      /// Where an element came from: its number in the file and its line
      /// (0: not known).
      struct Origin
      {
        std::int64_t number;
        std::size_t  line;
      };

      std::vector<Point<3>>    vertices;
      std::vector<CellData<3>> cells;
      std::vector<Origin>      cell_origins;
      SubCellData              faces;
      std::vector<Origin>      face_origins;
      /// What the format calls an element ("element", "cell").
      std::string element_word = "element";

      /// Add a tetrahedron with its material id, or a boundary triangle with
      /// its boundary id, and where it came from.
      void
      add_tetrahedron(std::vector<unsigned int> points,
                      types::material_id        id,
                      const Origin             &origin);
      void
      add_triangle(std::vector<unsigned int> points,
                   types::boundary_id        id,
                   const Origin             &origin);

      /// "element 17 (line 204)", or "cell 17" without a line.
      std::string
      name(const Origin &origin) const;
    };

    /**
     * Refuse, through @p fail, a point of @p points with a coordinate that is
     * not finite or is larger in magnitude than Mesh::largest_coordinate.
     */
    void
    check_points(const std::vector<Point<3>>                    &points,
                 const std::function<void(const std::string &)> &fail);

    /**
     * Check @p data as deal.II's debug-only assertions would, and more, then
     * build @p triangulation from it. Refused, with the element's name:
     * a vertex index out of range, a tetrahedron that repeats a vertex, two
     * tetrahedra on the same four vertices, a triangle that three or more
     * tetrahedra share, a boundary triangle that is no face of any
     * tetrahedron, two boundary triangles on the same face with different
     * ids, coordinates that are not finite or larger in magnitude than
     * Mesh::largest_coordinate, an empty mesh. A boundary triangle on an
     * interior face carries no boundary and is dropped (as a surface gmsh
     * embeds between two volumes). Unused points are removed. The cells are
     * put in Hilbert order (order_for_locality()); the result names each
     * of them as the file did.
     */
    CellNamer
    build_triangulation(MeshData          &data,
                        const std::string &filename,
                        Triangulation<3>  &triangulation);
  } // namespace Mesh
} // namespace softface

#endif

#ifndef softface_vtu_reader_h
#define softface_vtu_reader_h

#include <deal.II/grid/tria.h>

#include <softface/core/mesh.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Mesh
  {
    /**
     * Read a VTK XML unstructured grid (.vtu) as ParaView, VTK, meshio or a
     * parallel writer save it: DataArrays in ascii, inline binary (base64) or
     * appended raw form, optionally zlib-compressed, with 32- or 64-bit
     * headers and indices, little-endian. Every Piece is read; the points
     * that several pieces share (same coordinates) are merged, so that the
     * mesh conforms across pieces, and cells marked as ghost copies
     * (vtkGhostType) are skipped. Tetrahedra (VTK type 10) become cells,
     * triangles (type 5) boundary faces, vertices and lines are skipped;
     * anything else is an error. The first cell data array named MaterialID,
     * material_id, gmsh:physical or CellEntityIds gives the material ids of
     * tetrahedra and the boundary ids of triangles (whole numbers 0 to 255).
     * A parallel record (.pvtu, as deal.II's write_pvtu_record() and
     * ParaView write it) is read as the pieces of the .vtu files its Pieces
     * name, relative to its folder.
     * Whatever cannot be read completely throws one softface::Error,
     * "Cannot read mesh file '<filename>': <reason>."
     */
    CellNamer
    read_vtu(const std::string &filename, Triangulation<3> &triangulation);

    /// One point data array of a .vtu or .pvtu file.
    struct PointField
    {
      /// Every point of every piece, in the file's order: the points that
      /// pieces share appear once per piece, as written.
      std::vector<Point<3>> points;
      /// Values per point (1 for a scalar, 3 for a vector).
      unsigned int n_components = 0;
      /// n_components values per point, point after point.
      std::vector<double> values;
    };

    /**
     * The point data array @p name of a .vtu file or of every piece of a
     * parallel record (.pvtu), in the formats read_vtu() reads. A piece
     * without the array (unless it has no points), a count that does not
     * match its points, or pieces that disagree on the number of components
     * throw one softface::Error naming the file and the array.
     */
    PointField
    read_vtu_point_field(const std::string &filename, const std::string &name);
  } // namespace Mesh
} // namespace softface

#endif

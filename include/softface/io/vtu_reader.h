#ifndef softface_vtu_reader_h
#define softface_vtu_reader_h

#include <deal.II/grid/tria.h>

#include <string>

namespace softface
{
  using namespace dealii;

  namespace Mesh
  {
    /**
     * Read a VTK XML unstructured grid (.vtu) as ParaView, VTK or meshio
     * write it: DataArrays in ascii, inline binary (base64) or appended raw
     * form, optionally zlib-compressed, with 32- or 64-bit headers and
     * indices. Tetrahedra (VTK type 10) become cells, triangles (type 5)
     * boundary faces, vertices and lines are skipped; anything else is an
     * error. The first cell data array named MaterialID, material_id,
     * gmsh:physical or CellEntityIds gives the material ids of tetrahedra and
     * the boundary ids of triangles.
     */
    void
    read_vtu(const std::string &filename, Triangulation<3> &triangulation);
  } // namespace Mesh
} // namespace softface

#endif

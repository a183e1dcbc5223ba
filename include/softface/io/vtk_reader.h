#ifndef softface_io_vtk_reader_h
#define softface_io_vtk_reader_h

#include <softface/io/mesh_data.h>

#include <string>

namespace softface
{
  namespace Mesh
  {
    /**
     * Read a legacy VTK file (ASCII, DATASET UNSTRUCTURED_GRID, versions 2
     * to 5.1 with their two cell layouts): tetrahedra (type 10) become
     * cells, triangles (5) boundary faces, vertices (1) and lines (3) are
     * skipped. The first cell data array named MaterialID, material_id,
     * gmsh:physical or CellEntityIds (SCALARS or FIELD) gives the material
     * ids of tetrahedra and the boundary ids of triangles, whole numbers.
     * Every count is checked against the file's size and against the
     * others, every point index against the points, every cell type
     * against its point count; BINARY files and other datasets are refused
     * by name. Errors name the file and line.
     */
    MeshData
    read_legacy_vtk(const std::string &filename);
  } // namespace Mesh
} // namespace softface

#endif

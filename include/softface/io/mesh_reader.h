#ifndef softface_io_mesh_reader_h
#define softface_io_mesh_reader_h

#include <deal.II/grid/tria.h>

#include <softface/core/mesh.h>

#include <string>

namespace softface
{
  using namespace dealii;

  namespace Mesh
  {
    /**
     * Read a tetrahedral mesh: gmsh .msh (ASCII format 1, 2 or 4.1; physical
     * volumes become material ids, physical surfaces boundary ids), legacy VTK
     * .vtk (CELL_DATA "MaterialID"), or VTK XML .vtu (see read_vtu(); deal.II's
     * serialised .vtu too). Errors name the file. The cells are renumbered
     * for locality (all but deal.II's own serialised .vtu, which keeps its
     * order); the result names each as the file did (empty: "cell i").
     */
    CellNamer
    read_file(const std::string &filename, Triangulation<3> &triangulation);
  } // namespace Mesh
} // namespace softface

#endif

#ifndef softface_io_gmsh_reader_h
#define softface_io_gmsh_reader_h

#include <softface/io/mesh_data.h>

#include <string>

namespace softface
{
  namespace Mesh
  {
    /**
     * Read a gmsh .msh file, ASCII format 1, 2.x or 4.1, as deal.II's
     * GridIn::read_msh() reads it (physical volumes give the tetrahedra's
     * material ids, physical surfaces the triangles' boundary ids, 0 where
     * an entity has none; points and lines are skipped), but checked word
     * by word: every count against the file's size, every number whole or
     * finite as it must be, node tags unique and known, element types with
     * their node counts. Binary files, formats 3 and 4.0, and elements
     * other than tetrahedra, triangles, lines and points are refused by
     * name. Errors name the file and line.
     */
    MeshData
    read_gmsh(const std::string &filename);
  } // namespace Mesh
} // namespace softface

#endif

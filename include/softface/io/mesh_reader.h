#ifndef softface_io_mesh_reader_h
#define softface_io_mesh_reader_h

#include <deal.II/base/mpi.h>
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

    /**
     * read_file() on every rank of @p communicator, each into its own
     * triangulation (every rank holds the scene). If a rank
     * cannot read it (a file another node does not see, a partial copy),
     * every rank throws the same Error, the first such rank's message,
     * naming the rank unless it is rank 0: none is left alone in the
     * collectives that follow. Collective.
     */
    CellNamer
    read_file_on_every_rank(const MPI_Comm     communicator,
                            const std::string &filename,
                            Triangulation<3>  &triangulation);
  } // namespace Mesh
} // namespace softface

#endif

// Reading mesh files (io): gmsh .msh, legacy VTK and VTK XML .vtu by
// extension, each into the scene's triangulation, every failure one message
// that names the file. Called by Scene; the cells are checked afterwards.

#include <deal.II/grid/grid_in.h>

#include <softface/core/error.h>
#include <softface/io/gmsh_reader.h>
#include <softface/io/mesh_data.h>
#include <softface/io/mesh_reader.h>
#include <softface/io/vtk_reader.h>
#include <softface/io/vtu_reader.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace softface
{
  namespace Mesh
  {
    CellNamer
    read_file(const std::string &filename, Triangulation<3> &triangulation)
    {
      // A device or a fifo (/dev/zero) would be read without end, and a
      // directory opens as an empty stream on Linux.
      if (std::filesystem::exists(filename) &&
          !std::filesystem::is_regular_file(filename))
        throw Error("Mesh file '" + filename + "' is not a regular file.");
      std::ifstream in(filename);
      if (!in)
        throw Error("Cannot open mesh file '" + filename +
                    "' (Scene/Mesh file is relative to the parameter "
                    "file's folder).");

      const auto        dot = filename.rfind('.');
      const std::string extension =
        (dot == std::string::npos) ? "" : filename.substr(dot + 1);

      triangulation.clear();
      GridIn<3> grid_in(triangulation);
      CellNamer cell_name;
      try
        {
          // softface's own readers: deal.II's check their input with
          // debug-only assertions.
          if (extension == "msh")
            {
              MeshData data = read_gmsh(filename);
              cell_name = build_triangulation(data, filename, triangulation);
            }
          else if (extension == "vtk")
            {
              MeshData data = read_legacy_vtk(filename);
              cell_name = build_triangulation(data, filename, triangulation);
            }
          else if (extension == "vtu")
            {
              // deal.II reads only its own serialised .vtu; everything else
              // (ParaView, VTK, meshio) goes through softface's reader.
              std::ostringstream head;
              head << in.rdbuf();
              if (head.str().find("<dealiiData") != std::string::npos)
                {
                  std::istringstream again(head.str());
                  grid_in.read_vtu(again);
                  // The checks of softface's readers on what deal.II read.
                  check_points(triangulation.get_vertices(),
                               [&](const std::string &message) {
                                 throw Error("Cannot read mesh file '" +
                                             filename + "': " + message + ".");
                               });
                }
              else
                cell_name = read_vtu(filename, triangulation);
            }
          else if (extension == "pvtu")
            cell_name = read_vtu(filename, triangulation);
          else
            throw Error("Mesh file '" + filename + "': unknown format '." +
                        extension +
                        "' (softface reads .msh, .vtk, .vtu and .pvtu).");
        }
      catch (const Error &)
        {
          throw;
        }
      catch (const std::exception &e)
        {
          throw Error("Cannot read mesh file '" + filename +
                      "': " + error_message(e));
        }
      if (triangulation.n_active_cells() == 0)
        throw Error("Mesh file '" + filename + "' holds no cells.");
      return cell_name;
    }

    CellNamer
    read_file_on_every_rank(const MPI_Comm     communicator,
                            const std::string &filename,
                            Triangulation<3>  &triangulation)
    {
      if (Utilities::MPI::n_mpi_processes(communicator) == 1)
        return read_file(filename, triangulation);
      CellNamer   cell_name;
      std::string error;
      try
        {
          cell_name = read_file(filename, triangulation);
        }
      catch (const Error &e)
        {
          error = e.what();
          if (error.empty())
            error = "Cannot read mesh file '" + filename + "'.";
        }
      const auto errors = Utilities::MPI::all_gather(communicator, error);
      // Named by their rank in MPI_COMM_WORLD (@p communicator may be some
      // of its ranks: the roots of groups).
      const auto world_ranks = Utilities::MPI::all_gather(
        communicator, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD));
      for (unsigned int rank = 0; rank < errors.size(); ++rank)
        if (!errors[rank].empty())
          throw Error(world_ranks[rank] == 0 ?
                        errors[rank] :
                        "MPI rank " + std::to_string(world_ranks[rank]) + ": " +
                          errors[rank]);
      return cell_name;
    }
  } // namespace Mesh
} // namespace softface

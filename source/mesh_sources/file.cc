// The mesh source 'file' (mesh_sources): a mesh read from 'Scene/Mesh file'
// (gmsh, legacy VTK or VTK XML), on every rank that holds cells.

#include <softface/core/error.h>
#include <softface/core/mesh_source.h>
#include <softface/io/mesh_reader.h>

namespace softface
{
  namespace MeshSources
  {
    class File : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm,
                         const std::vector<std::string> &)
      {
        prm.declare_entry(
          "Mesh file",
          "",
          Patterns::Anything(),
          "Mesh to read when 'Mesh source = file': gmsh .msh "
          "(ASCII formats 1, 2 or 4.1; physical volumes give material "
          "ids, physical surfaces boundary ids), legacy VTK .vtk "
          "(ASCII; cell data MaterialID), or VTK "
          "XML .vtu (ascii, binary or appended raw, zlib or not; cell "
          "data MaterialID, material_id or gmsh:physical). Relative "
          "to the parameter file's folder. Coordinates are millimetres, "
          "at most 1e9 in magnitude.");
      }

      void
      parse_parameters(ParameterHandler  &prm,
                       const std::string &input_directory,
                       const std::string &) override
      {
        file = prm.get("Mesh file");
        if (file.empty())
          throw Error("Scene: 'Mesh source = file' needs a 'Mesh file'.");
        if (file[0] != '/' && !input_directory.empty())
          file = input_directory + "/" + file;
      }

      MadeMesh
      make_mesh(std::vector<BoneSegment> &,
                Triangulation<3> &triangulation,
                const MPI_Comm    mesh_readers,
                std::ostream *) override
      {
        MadeMesh made;
        if (mesh_readers != MPI_COMM_NULL)
          made.cell_name =
            Mesh::read_file_on_every_rank(mesh_readers, file, triangulation);
        made.description = "'" + file + "'";
        return made;
      }

    private:
      std::string file;
    };

    SOFTFACE_REGISTER_MESH_SOURCE(File, "file", "reads 'Mesh file'")
  } // namespace MeshSources
} // namespace softface

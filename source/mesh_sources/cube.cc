// The mesh source 'cube' (mesh_sources): the cube benchmark of Mollemans et al.
// 2007, generated (subsection Scene/Cube).

#include <softface/core/mesh_source.h>

namespace softface
{
  namespace MeshSources
  {
    class Cube : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm,
                         const std::vector<std::string> &)
      {
        Mesh::CubeParameters::declare_parameters(prm);
      }

      void
      parse_parameters(ParameterHandler &prm,
                       const std::string &,
                       const std::string &) override
      {
        parameters.parse_parameters(prm);
      }

      MadeMesh
      make_mesh(std::vector<BoneSegment> &,
                Triangulation<3> &triangulation,
                const MPI_Comm    mesh_readers,
                std::ostream *) override
      {
        if (mesh_readers != MPI_COMM_NULL)
          Mesh::generate_cube(parameters, triangulation);
        MadeMesh made;
        made.description = "generated cube";
        return made;
      }

    private:
      Mesh::CubeParameters parameters;
    };

    SOFTFACE_REGISTER_MESH_SOURCE(
      Cube,
      "cube",
      "generates the cube benchmark of Mollemans et al. 2007 (subsection Cube)")
  } // namespace MeshSources
} // namespace softface

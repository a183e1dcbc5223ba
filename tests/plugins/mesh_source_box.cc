// A mesh source is one file: this one, registered in one line and chosen by
// 'Scene/Mesh source = box' (mesh_source_box.prm), makes a box of
// tetrahedra with deal.II's GridGenerator, the lower front cells bone
// (material id 2) and the back face held (boundary id 1), what the default
// segments 'bone' and 'fixed' look for. Linear FEM and the mass tensor
// model run on it through the whole simulator; the mass tensor model
// converges to linear FEM's equations, so their answers agree to its stop
// threshold, which they would not on a mesh the source got wrong.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/mesh_source.h>
#include <softface/core/vec3_parameter.h>

#include "../run_scene.h"

namespace
{
  using namespace dealii;

  class Box : public softface::MeshSources::Interface
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm, const std::vector<std::string> &)
    {
      prm.enter_subsection("Box");
      prm.declare_entry("Size",
                        "40, 40, 20",
                        Patterns::Anything(),
                        "Edge lengths in x, y, z (mm).");
      prm.declare_entry("Cells per edge",
                        "4",
                        Patterns::Integer(2, 64),
                        "Hexahedra along each edge, each split into "
                        "tetrahedra.");
      prm.leave_subsection();
    }

    void
    parse_parameters(ParameterHandler &prm,
                     const std::string &,
                     const std::string &) override
    {
      prm.enter_subsection("Box");
      size = softface::parse_vec3(prm.get("Size"), "Scene/Box/Size");
      n    = prm.get_integer("Cells per edge");
      prm.leave_subsection();
    }

    softface::MeshSources::MadeMesh
    make_mesh(std::vector<softface::BoneSegment> &,
              Triangulation<3> &triangulation,
              const MPI_Comm    mesh_readers,
              std::ostream *) override
    {
      if (mesh_readers != MPI_COMM_NULL)
        {
          GridGenerator::subdivided_hyper_rectangle_with_simplices(
            triangulation,
            {n, n, n},
            Point<3>(),
            Point<3>(size[0], size[1], size[2]));
          for (const auto &cell : triangulation.active_cell_iterators())
            {
              const Point<3> c = cell->center();
              if (c[2] < size[2] / n && c[1] < size[1] / 2)
                cell->set_material_id(2);
              for (const auto &face : cell->face_iterators())
                if (face->at_boundary() &&
                    std::abs(face->center()[1] - size[1]) < 1e-9 * size[1])
                  face->set_boundary_id(1);
            }
        }
      softface::MeshSources::MadeMesh made;
      made.description = "box";
      return made;
    }

  private:
    std::array<double, 3> size;
    unsigned int          n = 4;
  };

  SOFTFACE_REGISTER_MESH_SOURCE(Box, "box", "a box of tetrahedra (test)")
} // namespace

SOFTFACE_TEST(mesh_source_box)
{
  softface::Simulator simulator;
  const int           exit_code = softface_tests::run_scene(
    simulator, softface_tests::source_file("plugins/mesh_source_box.prm"));
  softface_tests::check_equal("exit code", exit_code, 0);
  deallog << "mesh: " << simulator.scene().mesh_description << ", "
          << simulator.scene().triangulation.n_active_cells() << " tetrahedra"
          << std::endl;
}

// VTK XML meshes as other tools write them: the unit cube in six tetrahedra
// written by tests/data/vtu/make_vtu.py (independent of the reader, after the
// VTK specification) as ascii, inline binary + zlib with 64-bit headers,
// appended raw, and appended + zlib. Each must give 6 tetrahedra of total
// volume 1 with material id 7, and boundary ids 3 on the two triangles of
// z = 0 and 4 on the ten others.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include "tests.h"
#include <softface/core/mesh.h>
#include <softface/core/tetrahedron.h>
#include <softface/io/mesh_reader.h>

using namespace softface;

SOFTFACE_TEST(vtu_formats)
{
  for (const std::string name :
       {"ascii", "binary_zlib", "appended_raw", "appended_zlib"})
    {
      Triangulation<3> tria;
      Mesh::read_file(softface_tests::source_file("data/vtu/cube6_" + name +
                                                  ".vtu"),
                      tria);
      Mesh::check_cells(tria, name);
      double       volume       = 0.;
      unsigned int n_material_7 = 0, n_id_3 = 0, n_id_4 = 0, n_bottom = 0;
      for (const auto &cell : tria.active_cell_iterators())
        {
          volume += Tetrahedron::signed_volume(Tetrahedron::vertices(cell));
          n_material_7 += (cell->material_id() == 7);
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                n_id_3 += (face->boundary_id() == 3);
                n_id_4 += (face->boundary_id() == 4);
                n_bottom +=
                  (face->center()[2] == 0.) && (face->boundary_id() == 3);
              }
        }
      deallog << name << ": " << tria.n_active_cells() << " cells, "
              << tria.n_used_vertices() << " vertices" << std::endl;
      softface_tests::check_below(name + ": |volume - 1|",
                                  std::abs(volume - 1.),
                                  1e-14);
      softface_tests::check_equal(name + ": cells with material id 7",
                                  n_material_7,
                                  6);
      softface_tests::check_equal(name + ": faces with boundary id 3",
                                  n_id_3,
                                  2);
      softface_tests::check_equal(name + ": of them at z = 0", n_bottom, 2);
      softface_tests::check_equal(name + ": faces with boundary id 4",
                                  n_id_4,
                                  10);
    }
}

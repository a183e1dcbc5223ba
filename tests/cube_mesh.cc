// The generated cube (seed 2.3.6): its tetrahedra fill [0,L]^3 exactly, do not
// overlap or leave gaps (the boundary area is exactly 6 L^2, which a
// non-conforming split would exceed), conform to the inner cube (material 2
// fills exactly s^3 and its vertices lie in the closed inner box), carry
// boundary id 1 on every outer face, and come near the requested count.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/mesh.h>

#include "tests.h"

using namespace softface;

SOFTFACE_TEST(cube_mesh)
{
  for (const unsigned int target : {10000u, 30000u, 100000u})
    {
      Mesh::CubeParameters parameters;
      parameters.target_n_tetrahedra = target;
      Triangulation<3> tria;
      Mesh::generate_cube(parameters, tria);
      Mesh::check_cells(tria, "generated cube");

      const double L = 80., a = 35., b = 45.;
      double       volume = 0., inner_volume = 0., boundary_area = 0.;
      bool         inner_vertices_in_box = true, boundary_ids_ok = true;
      for (const auto &cell : tria.active_cell_iterators())
        {
          const double v = Mesh::signed_volume({{cell->vertex(0),
                                                 cell->vertex(1),
                                                 cell->vertex(2),
                                                 cell->vertex(3)}});
          volume += v;
          if (cell->material_id() == Mesh::cube_inner_id)
            {
              inner_volume += v;
              for (const unsigned int i : cell->vertex_indices())
                for (unsigned int d = 0; d < 3; ++d)
                  inner_vertices_in_box &= (cell->vertex(i)[d] >= a - 1e-12 &&
                                            cell->vertex(i)[d] <= b + 1e-12);
            }
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                boundary_area +=
                  0.5 * cross_product_3d(face->vertex(1) - face->vertex(0),
                                         face->vertex(2) - face->vertex(0))
                          .norm();
                boundary_ids_ok &=
                  (face->boundary_id() == Mesh::cube_outer_face);
              }
        }
      deallog << "target " << target << std::endl;
      softface_tests::check(std::abs(double(tria.n_active_cells()) - target) <
                              0.25 * target,
                            "tetrahedron count within 25% of target");
      softface_tests::check(std::abs(volume - L * L * L) < 1e-9 * L * L * L,
                            "volume is L^3");
      softface_tests::check(std::abs(boundary_area - 6 * L * L) < 1e-9 * L * L,
                            "boundary area is 6 L^2 (conforming)");
      softface_tests::check(std::abs(inner_volume - 1000.) < 1e-9,
                            "inner material volume is s^3");
      softface_tests::check(inner_vertices_in_box,
                            "inner cells lie in the inner box");
      softface_tests::check(boundary_ids_ok, "outer faces carry id 1");
    }
}

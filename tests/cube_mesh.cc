// The generated cube (Mollemans et al. 2007, Sec. 2.3.6): its tetrahedra fill
// [0,L]^3 exactly, do not overlap or leave gaps (the boundary area is exactly
// 6 L^2, which a non-conforming split would exceed), conform to the inner cube
// (material 2 fills exactly s^3 and its vertices lie in the closed inner box),
// carry boundary id 1 on every outer face, and come near the requested count.
// Graded grids keep all of that and crowd their lines towards the inner
// cube's face planes: the spacing at those planes is about 1/Grading of the
// spacing at the outer faces. The mirror-symmetric split gives a mesh that
// each reflection x_d -> L - x_d maps onto itself (cell centroids compared).

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/mesh.h>
#include <softface/core/tetrahedron.h>

#include "tests.h"

#include <array>
#include <set>
#include <tuple>

using namespace softface;

SOFTFACE_TEST(cube_mesh)
{
  for (const auto &[target, grading, symmetric] :
       {std::make_tuple(10000u, 1., false),
        std::make_tuple(30000u, 1., false),
        std::make_tuple(100000u, 1., false),
        std::make_tuple(30000u, 6., false),
        std::make_tuple(100000u, 6., false),
        std::make_tuple(30000u, 1., true),
        std::make_tuple(30000u, 6., true)})
    {
      Mesh::CubeParameters parameters;
      parameters.target_n_tetrahedra = target;
      parameters.grading             = grading;
      parameters.mirror_symmetric    = symmetric;
      Triangulation<3> tria;
      Mesh::generate_cube(parameters, tria);
      Mesh::check_cells(tria, "generated cube");

      const double L = 80., a = 35., b = 45.;
      double       volume = 0., inner_volume = 0., boundary_area = 0.;
      unsigned int inner_vertices_outside = 0, faces_not_outer = 0;
      for (const auto &cell : tria.active_cell_iterators())
        {
          const double v =
            Tetrahedron::signed_volume(Tetrahedron::vertices(cell));
          volume += v;
          if (cell->material_id() == Mesh::cube_inner_id)
            {
              inner_volume += v;
              for (const unsigned int i : cell->vertex_indices())
                for (unsigned int d = 0; d < 3; ++d)
                  inner_vertices_outside += !(cell->vertex(i)[d] >= a - 1e-12 &&
                                              cell->vertex(i)[d] <= b + 1e-12);
            }
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                boundary_area +=
                  0.5 * cross_product_3d(face->vertex(1) - face->vertex(0),
                                         face->vertex(2) - face->vertex(0))
                          .norm();
                faces_not_outer +=
                  (face->boundary_id() != Mesh::cube_outer_face);
              }
        }
      deallog << "target " << target << ", grading " << grading
              << (symmetric ? ", mirror-symmetric" : "") << ": "
              << tria.n_active_cells() << " tetrahedra, " << tria.n_vertices()
              << " vertices" << std::endl;
      softface_tests::check_below(
        "|tetrahedra / target - 1|",
        std::abs(double(tria.n_active_cells()) / target - 1.),
        0.25,
        3);
      softface_tests::check_below("|volume - L^3| / L^3",
                                  std::abs(volume - L * L * L) / (L * L * L),
                                  1e-11);
      softface_tests::check_below(
        "|boundary area - 6 L^2| / 6 L^2 (conforming)",
        std::abs(boundary_area - 6 * L * L) / (6 * L * L),
        1e-11);
      softface_tests::check_below("|inner material volume - s^3| / s^3",
                                  std::abs(inner_volume - 1000.) / 1000.,
                                  1e-11);
      softface_tests::check_equal("inner cells' vertex coordinates outside "
                                  "the inner box",
                                  inner_vertices_outside,
                                  0);
      softface_tests::check_equal("outer faces without id 1",
                                  faces_not_outer,
                                  0);

      // Grid lines along x: the spacing next to the inner face x = a against
      // the spacing next to the outer face x = 0.
      std::set<double> lines;
      for (const auto &vertex : tria.get_vertices())
        lines.insert(vertex[0]);
      const std::vector<double> x(lines.begin(), lines.end());
      const auto   at_a  = std::lower_bound(x.begin(), x.end(), a - 1e-9);
      const double ratio = (x[1] - x[0]) / (*at_a - *(at_a - 1));
      softface_tests::check_equal("x = 35 is a grid plane", *at_a == a, 1);
      softface_tests::check_below(
        "|spacing at the outer face / at the inner face / grading - 1|",
        std::abs(ratio / grading - 1.),
        0.3,
        3);

      if (symmetric)
        {
          // Centroids on a 1e-6 mm lattice; a reflection must map the set
          // onto itself.
          const auto key = [](const Point<3> &p) {
            return std::array<long, 3>{{std::lround(p[0] * 1e6),
                                        std::lround(p[1] * 1e6),
                                        std::lround(p[2] * 1e6)}};
          };
          std::set<std::array<long, 3>> centroids;
          for (const auto &cell : tria.active_cell_iterators())
            centroids.insert(key(cell->center()));
          unsigned int not_mirrored = 0;
          for (unsigned int d = 0; d < 3; ++d)
            for (const auto &cell : tria.active_cell_iterators())
              {
                Point<3> image = cell->center();
                image[d]       = L - image[d];
                not_mirrored += (centroids.count(key(image)) != 1);
              }
          softface_tests::check_equal(
            "cell centroids that a reflection maps onto no centroid",
            not_mirrored,
            0);
        }
    }
}

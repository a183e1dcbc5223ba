// Gelder's spring constants (Mollemans et al. 2007, eq. 5),
// k = E sum(V) / L0^2, by hand: a regular tetrahedron of edge 2 sqrt(2) has
// volume 8/3, so with E = 1 N/mm^2 every spring has k = (8/3) / 8 = 1/3 N/mm.
// Mirroring it through a face adds a second regular tetrahedron: the three
// shared edges then carry both volumes (k = 2/3), the six others one
// (k = 1/3), nine springs in all.

#include <softface/core/tetrahedron.h>
#include <softface/models/mass_spring.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  void
  check_springs(const std::vector<Point<3>> &points,
                std::vector<CellData<3>>     cells,
                const std::string           &name,
                const unsigned int           n_springs,
                const unsigned int           n_shared)
  {
    for (auto &cell : cells)
      if (Tetrahedron::signed_volume({{points[cell.vertices[0]],
                                       points[cell.vertices[1]],
                                       points[cell.vertices[2]],
                                       points[cell.vertices[3]]}}) < 0)
        std::swap(cell.vertices[1], cell.vertices[2]);
    Scene scene;
    scene.triangulation.create_triangulation(points, cells, SubCellData());
    scene.material.youngs_modulus_pa = 1e6;
    scene.segments                   = {{"all", {0}, {}, {}}};
    scene.setup();
    Models::MassSpring msm;
    msm.setup(scene);

    // A spring's constant by hand: 2/3 N/mm on an edge that both
    // tetrahedra share (both end points on the mirror face 1, 2, 3), 1/3 on
    // the others.
    double       largest_error  = 0.;
    unsigned int n_shared_found = 0;
    for (const auto &spring : msm.springs())
      {
        const bool shared = (cells.size() == 2 && spring.a != 0 &&
                             spring.a != 4 && spring.b != 0 && spring.b != 4);
        n_shared_found += shared;
        largest_error =
          std::max(largest_error,
                   std::abs(spring.stiffness - (shared ? 2. : 1.) / 3.));
      }
    softface_tests::check_equal(name + ": springs",
                                msm.springs().size(),
                                n_springs);
    softface_tests::check_equal(name + ": springs on shared edges",
                                n_shared_found,
                                n_shared);
    softface_tests::check_below(name + ": largest |k - k_by_hand| (N/mm)",
                                largest_error,
                                1e-14);
  }
} // namespace

SOFTFACE_TEST(mass_spring_constants)
{
  const std::vector<Point<3>> points = {Point<3>(1, 1, 1),
                                        Point<3>(1, -1, -1),
                                        Point<3>(-1, 1, -1),
                                        Point<3>(-1, -1, 1),
                                        Point<3>(-5. / 3, -5. / 3, -5. / 3)};
  CellData<3>                 first(4), second(4);
  first.vertices  = {0, 1, 2, 3};
  second.vertices = {4, 1, 2, 3};
  check_springs(
    {points.begin(), points.begin() + 4}, {first}, "regular tetrahedron", 6, 0);
  check_springs(points, {first, second}, "two tetrahedra", 9, 3);
}

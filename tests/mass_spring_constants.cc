// Gelder's spring constants (seed eq. 5), k = E sum(V) / L0^2, by hand:
// a regular tetrahedron of edge 2 sqrt(2) has volume 8/3, so with E = 1
// N/mm^2 every spring has k = (8/3) / 8 = 1/3 N/mm. Mirroring it through a
// face adds a second regular tetrahedron: the three shared edges then carry
// both volumes (k = 2/3), the six others one (k = 1/3), nine springs in all.

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
      if (Mesh::signed_volume({{points[cell.vertices[0]],
                                points[cell.vertices[1]],
                                points[cell.vertices[2]],
                                points[cell.vertices[3]]}}) < 0)
        std::swap(cell.vertices[1], cell.vertices[2]);
    Scene scene;
    scene.triangulation.create_triangulation(points, cells, SubCellData());
    scene.material.youngs_modulus_pa = 1e6;
    scene.segments                   = {{"all", {0}, {}}};
    scene.setup();
    Models::MassSpring msm;
    msm.setup(scene);

    unsigned int n_one_third = 0, n_two_thirds = 0;
    for (const auto &spring : msm.springs())
      {
        n_one_third += std::abs(spring.stiffness - 1. / 3.) < 1e-14;
        n_two_thirds += std::abs(spring.stiffness - 2. / 3.) < 1e-14;
      }
    deallog << name << ": " << msm.springs().size() << " springs" << std::endl;
    softface_tests::check(msm.springs().size() == n_springs &&
                            n_two_thirds == n_shared &&
                            n_one_third == n_springs - n_shared,
                          name + ": every spring constant as computed by hand");
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

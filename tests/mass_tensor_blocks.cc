// The mass tensors K_jj and K_jk (seed eqs. 6-10) are exactly the 3x3 blocks
// of the linear FEM stiffness matrix (relative 1e-12), on a distorted mesh
// with two materials' worth of distinct element shapes; and K_jk is zero
// exactly where the FEM matrix has no block (points sharing no tetrahedron).

#include <deal.II/grid/grid_tools.h>

#include <softface/models/linear_fem.h>
#include <softface/models/mass_tensor.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(mass_tensor_blocks)
{
  Scene                scene;
  Mesh::CubeParameters cube;
  cube.target_n_tetrahedra = 3000;
  Mesh::generate_cube(cube, scene.triangulation);
  GridTools::transform(
    [](const Point<3> &x) {
      const double s = std::sin(M_PI * x[0] / 80) * std::sin(M_PI * x[1] / 80) *
                       std::sin(M_PI * x[2] / 80);
      return x + Point<3>(3. * s, -2. * s * std::cos(x[2]), 2.5 * s);
    },
    scene.triangulation);
  scene.segments = {{"fixed", {}, {Mesh::cube_outer_face}},
                    {"bone", {Mesh::cube_inner_id}, {}}};
  scene.setup();

  Models::LinearFEM fem;
  fem.set_solver("direct", 0.);
  fem.setup(scene);
  Models::MassTensor mtm;
  mtm.setup(scene);
  const SparseMatrix<double> &K = fem.stiffness_matrix();

  double       max_entry = 0., max_difference = 0.;
  unsigned int n_blocks = 0, n_mismatched_structure = 0;
  for (unsigned int j = 0; j < mtm.n_points(); ++j)
    {
      std::set<unsigned int> fem_neighbours;
      for (unsigned int r = 0; r < 3; ++r)
        for (auto entry = K.begin(3 * j + r); entry != K.end(3 * j + r);
             ++entry)
          fem_neighbours.insert(entry->column() / 3);
      for (const unsigned int k : fem_neighbours)
        {
          const Tensor<2, 3> T = mtm.tensor(j, k);
          ++n_blocks;
          for (unsigned int r = 0; r < 3; ++r)
            for (unsigned int c = 0; c < 3; ++c)
              {
                max_entry =
                  std::max(max_entry, std::abs(K(3 * j + r, 3 * k + c)));
                max_difference =
                  std::max(max_difference,
                           std::abs(K(3 * j + r, 3 * k + c) - T[r][c]));
              }
        }
      // A point three grid steps away shares no tetrahedron with j.
      const unsigned int far = (j + mtm.n_points() / 2) % mtm.n_points();
      if (!fem_neighbours.count(far) && mtm.tensor(j, far).norm() != 0.)
        ++n_mismatched_structure;
    }
  deallog << "points: " << mtm.n_points() << ", blocks: " << n_blocks
          << std::endl;
  softface_tests::check(max_difference <= 1e-12 * max_entry,
                        "K_jj and K_jk equal the FEM blocks to 1e-12");
  softface_tests::check(n_mismatched_structure == 0,
                        "no tensor where FEM has no block");
}

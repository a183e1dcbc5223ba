// The mass tensors K_jj and K_jk (Mollemans et al. 2007, eqs. 6-10) are exactly
// the 3x3 blocks of the linear FEM stiffness matrix (relative 1e-12), on a
// distorted mesh with many distinct element shapes; and K_jk is zero exactly
// where the FEM matrix has no block (points sharing no tetrahedron).

#include <softface/models/linear_fem.h>
#include <softface/models/mass_tensor.h>

#include "scenes.h"
#include "tests.h"

#include <set>

using namespace softface;

SOFTFACE_TEST(mass_tensor_blocks)
{
  Scene scene;
  softface_tests::make_distorted_cube_scene(scene, 3000, true);

  Models::LinearFEM fem;
  fem.set_solver("direct", 0.);
  fem.setup(scene);
  Models::MassTensor mtm;
  mtm.setup(scene);
  const SparseMatrix<double> &K = fem.stiffness_matrix();

  double       max_entry = 0., max_difference = 0.;
  unsigned int n_blocks = 0, n_far = 0, n_mismatched_structure = 0;
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
      // A point half the numbering away shares no tetrahedron with j.
      const unsigned int far = (j + mtm.n_points() / 2) % mtm.n_points();
      if (!fem_neighbours.count(far))
        {
          ++n_far;
          if (mtm.tensor(j, far).norm() != 0.)
            ++n_mismatched_structure;
        }
    }
  deallog << "points: " << mtm.n_points() << ", blocks: " << n_blocks
          << ", far pairs: " << n_far << std::endl;
  softface_tests::check_below("max |K_FEM - K_MTM| / max |K_FEM|",
                              max_difference / max_entry,
                              1e-12);
  softface_tests::check_equal("far pairs with a nonzero tensor",
                              n_mismatched_structure,
                              0);
}

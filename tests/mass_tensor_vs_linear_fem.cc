// Run to full convergence (stop threshold 0), the mass tensor model solves
// the linear FEM equations: its answer equals the direct linear FEM solve to
// 1e-6 mm, in the seed's Gauss-Seidel order and over-relaxed (SOR 1.8), with
// a rotation in the planning so that all three components are exercised.

#include <softface/models/linear_fem.h>
#include <softface/models/mass_tensor.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(mass_tensor_vs_linear_fem)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 3000);
  const Vector<double> prescribed =
    softface_tests::move_bone(scene, Point<3>(1, -2, 6), 15.);

  Models::LinearFEM fem;
  fem.set_solver("direct", 0.);
  fem.setup(scene);
  Vector<double> reference;
  fem.solve(prescribed, reference);

  for (const double relaxation : {1.0, 1.8})
    {
      Models::MassTensor mtm;
      mtm.set_scheme(/*gauss_seidel=*/true, /*threshold=*/0., 10, true);
      mtm.set_relaxation(relaxation);
      mtm.setup(scene);
      Vector<double> u;
      mtm.solve(prescribed, u);
      Vector<double> difference = u;
      difference -= reference;
      softface_tests::check(difference.linfty_norm() < 1e-6,
                            "relaxation " +
                              softface_tests::rounded(relaxation) +
                              ": converged MTM equals linear FEM to 1e-6 mm");
    }
}

// Run to full convergence (stop threshold 0), the mass tensor model solves
// the linear FEM equations: its answer equals the direct linear FEM solve to
// 1e-6 mm, in the Gauss-Seidel order of Mollemans et al. 2007 and over-relaxed
// (SOR 1.8), with a rotation in the planning so that all three components are
// exercised. And the precision it reports at its default stop threshold
// (against the converged answer it computes from its own tensors) is the
// distance to the linear FEM answer.

#include <softface/core/displacement.h>
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
      const std::string name =
        "relaxation " + softface_tests::rounded(relaxation);
      softface_tests::check_below(name + ": max |u_MTM - u_linear fem| (mm)",
                                  difference.linfty_norm(),
                                  1e-6);
      softface_tests::print(name + ": sweeps", mtm.report().sweeps);
    }

  Models::MassTensor stopped;
  stopped.set_report_precision(true);
  stopped.setup(scene);
  Vector<double> u;
  stopped.solve(prescribed, u);
  const auto distance =
    Displacement::free_vertex_difference(scene, u, reference);
  softface_tests::print("default stop: precision max (mm)",
                        stopped.report().precision_max,
                        4);
  softface_tests::check_below(
    "default stop: |precision max - max |u - u_linear fem|| (mm)",
    std::abs(stopped.report().precision_max - distance.max),
    1e-9);
  softface_tests::check_below(
    "default stop: |precision mean - mean |u - u_linear fem|| (mm)",
    std::abs(stopped.report().precision_mean - distance.mean),
    1e-9);
}

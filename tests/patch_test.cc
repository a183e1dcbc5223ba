// Patch test: a linear (affine, non-rigid) displacement prescribed on the
// whole boundary of a distorted mesh is reproduced exactly at every interior
// vertex, because its constant strain is in equilibrium. Run with each of the
// three linear solvers; prints the largest relative error and the iterations.
// The bounds sit about 100 times above the round-off each solver reaches
// (numdiff's absolute floor of 1e-10 would hide an error growing from 1e-13
// to 1e-11): the iterative one stops at its tolerance of 1e-13, the others
// at machine precision.

#include <softface/models/linear_fem.h>

#include "scenes.h"
#include "tests.h"

#include <map>

using namespace softface;

SOFTFACE_TEST(patch_test)
{
  Scene scene;
  softface_tests::make_distorted_cube_scene(scene, 3000, false);

  Tensor<2, 3> A;
  A[0][0] = 0.01, A[0][1] = -0.02, A[0][2] = 0.005;
  A[1][0] = 0.015, A[1][1] = 0.03, A[1][2] = -0.01;
  A[2][0] = -0.004, A[2][1] = 0.02, A[2][2] = -0.025;
  const Tensor<1, 3> b = Point<3>(0.5, -1., 2.);

  Vector<double> exact(scene.dof_handler.n_dofs());
  const auto    &vertices = scene.triangulation.get_vertices();
  for (unsigned int v = 0; v < vertices.size(); ++v)
    for (unsigned int c = 0; c < 3; ++c)
      exact[scene.vertex_dofs()[v][c]] = (A * vertices[v] + b)[c];
  Vector<double> prescribed = exact;
  for (unsigned int i = 0; i < prescribed.size(); ++i)
    if (!scene.join_dofs()[i])
      prescribed[i] = 12345.; // must be ignored

  deallog << "free DoFs: " << scene.n_free_dofs() << std::endl;
  const std::map<std::string, double> bound = {{"gmres jacobi", 1e-11},
                                               {"cg amg", 1e-13},
                                               {"direct", 1e-13}};
  for (const auto &[solver, largest_error] : bound)
    {
      Models::LinearFEM model;
      model.set_solver(solver, 1e-13);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);
      softface_tests::check_below(solver + ": max |u - u_affine| / max |u|",
                                  softface_tests::relative_difference(u, exact),
                                  largest_error);
      softface_tests::print(solver + ": iterations",
                            model.statistics().iterations);
    }
}

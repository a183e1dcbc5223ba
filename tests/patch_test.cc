// Patch test: a linear (affine, non-rigid) displacement prescribed on the
// whole boundary of a distorted mesh is reproduced exactly at every interior
// vertex, because its constant strain is in equilibrium. Run with each of the
// three linear solvers.

#include <deal.II/grid/grid_tools.h>

#include <softface/models/linear_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(patch_test)
{
  Scene                scene;
  Mesh::CubeParameters cube;
  cube.target_n_tetrahedra = 3000;
  Mesh::generate_cube(cube, scene.triangulation);
  GridTools::transform(
    [](const Point<3> &x) {
      // Moves interior vertices only (the sine vanishes on the faces).
      const double s = std::sin(M_PI * x[0] / 80) * std::sin(M_PI * x[1] / 80) *
                       std::sin(M_PI * x[2] / 80);
      return x + Point<3>(2.5 * s, -1.5 * s, 2. * s);
    },
    scene.triangulation);
  scene.segments = {{"boundary", {}, {Mesh::cube_outer_face}}};
  scene.setup();

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
  for (const std::string solver : {"gmres jacobi", "cg amg", "direct"})
    {
      Models::LinearFEM model;
      model.set_solver(solver, 1e-13);
      model.setup(scene);
      Vector<double> u;
      model.solve(prescribed, u);
      softface_tests::check(softface_tests::relative_difference(u, exact) <
                              1e-9,
                            solver + ": affine field reproduced to 1e-9");
    }
}

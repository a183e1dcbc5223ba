// A scene whose every vertex is a join point (one segment holds every
// cell): there is nothing to solve for, and every model must still return
// the join motion itself, not zero (a nonlinear solve that stops at its
// zero first residual would return u = 0 as converged).

#include <softface/core/mesh.h>
#include <softface/models/interface.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(every_vertex_a_join_point)
{
  Scene                scene;
  Mesh::CubeParameters cube;
  cube.target_n_tetrahedra = 1000;
  Mesh::generate_cube(cube, scene.triangulation);
  scene.mesh_description = "generated cube";
  scene.segments         = {
            {"whole", {Mesh::cube_tissue_id, Mesh::cube_inner_id}, {}, {}}};
  scene.setup();
  deallog << "vertices: " << scene.n_vertices()
          << ", join points: " << scene.n_join_vertices(0) << std::endl;

  Planning planning;
  planning.set_motion(0,
                      RigidMotion(Point<3>(1, -2, 3),
                                  Point<3>(0, 0, 1),
                                  5.,
                                  Point<3>(40, 40, 40)));
  const Vector<double> prescribed = planning.prescribed_displacement(scene);
  softface_tests::print("max |prescribed| (mm)", prescribed.linfty_norm());

  for (const std::string &name : Models::registered_names())
    {
      ParameterHandler prm;
      Models::declare_parameters(prm);
      const auto model = Models::create(name, prm);
      model->setup(scene);
      Vector<double> u;
      model->solve(prescribed, u);
      Vector<double> difference = u;
      difference -= prescribed;
      softface_tests::check_below(name + ": max |u - prescribed| (mm)",
                                  difference.linfty_norm(),
                                  1e-12);
    }
}

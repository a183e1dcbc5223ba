// Nonlinear FEM against linear FEM and rigid motions:
// - small displacements (0.01 and 0.02 mm lifts): the difference to linear
//   FEM is O(u^2): tiny against u, and four times larger at twice the lift;
// - the bone alone rotated by 30 degrees (outer faces free): the whole block
//   follows rigidly with zero stress, which only the full Green-Lagrange
//   strain gives; linear FEM's answer is visibly not rigid;
// - the same model with 'Material law = linear' solves linear FEM's
//   equations: at a 30 degree rotation of the held bone, where the other
//   laws differ from linear FEM by millimetres, it equals linear FEM to
//   1e-9 relative, in at most two Newton iterations.

#include <softface/models/linear_fem.h>
#include <softface/models/nonlinear_fem.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  double
  max_difference_to_linear(const Scene          &scene,
                           const Vector<double> &prescribed,
                           const std::string    &law)
  {
    Models::LinearFEM linear;
    linear.set_solver("direct", 0.);
    linear.setup(scene);
    Models::NonlinearFEM nonlinear;
    nonlinear.set_options(law, "direct");
    nonlinear.setup(scene);
    Vector<double> u_linear, u_nonlinear;
    linear.solve(prescribed, u_linear);
    nonlinear.solve(prescribed, u_nonlinear);
    u_nonlinear -= u_linear;
    return u_nonlinear.linfty_norm();
  }
} // namespace

SOFTFACE_TEST(nonlinear_vs_linear)
{
  {
    Scene scene;
    softface_tests::make_cube_scene(scene, 3000);
    for (const std::string law : {"st venant-kirchhoff", "neo-hooke"})
      {
        const double d1 = max_difference_to_linear(
          scene, softface_tests::move_bone(scene, Point<3>(0, 0, 0.01)), law);
        const double d2 = max_difference_to_linear(
          scene, softface_tests::move_bone(scene, Point<3>(0, 0, 0.02)), law);
        softface_tests::check_below(law +
                                      ": 0.01 mm lift: max |u - u_linear| / "
                                      "lift",
                                    d1 / 0.01,
                                    1e-3);
        softface_tests::check_below(law +
                                      ": |difference ratio at twice the lift "
                                      "- 4|",
                                    std::abs(d2 / d1 - 4.),
                                    0.4);
      }
  }

  {
    Scene                scene;
    Mesh::CubeParameters cube;
    cube.target_n_tetrahedra = 3000;
    Mesh::generate_cube(cube, scene.triangulation);
    scene.segments = {{"bone", {Mesh::cube_inner_id}, {}, {}}};
    scene.setup();
    const RigidMotion motion(Point<3>(1, 2, -1),
                             Point<3>(1, 1, 1),
                             30.,
                             Point<3>(40, 40, 40));
    Planning          planning;
    planning.set_motion(0, motion);
    const Vector<double> prescribed = planning.prescribed_displacement(scene);

    Models::NonlinearFEM nonlinear;
    nonlinear.set_options("neo-hooke", "direct");
    nonlinear.setup(scene);
    Models::LinearFEM linear;
    linear.set_solver("direct", 0.);
    linear.setup(scene);
    Vector<double> u_nonlinear, u_linear;
    nonlinear.solve(prescribed, u_nonlinear);
    linear.solve(prescribed, u_linear);

    double      nonlinear_deviation = 0., linear_deviation = 0.;
    const auto &vertices = scene.triangulation.get_vertices();
    for (unsigned int v = 0; v < vertices.size(); ++v)
      for (unsigned int c = 0; c < 3; ++c)
        {
          const double rigid = motion.displacement(vertices[v])[c];
          const auto   dof   = scene.vertex_dofs()[v][c];
          nonlinear_deviation =
            std::max(nonlinear_deviation, std::abs(u_nonlinear[dof] - rigid));
          linear_deviation =
            std::max(linear_deviation, std::abs(u_linear[dof] - rigid));
        }
    softface_tests::check_below(
      "free block turned 30 degrees: nonlinear FEM's deviation from the "
      "rigid motion (mm)",
      nonlinear_deviation,
      1e-8);
    softface_tests::check_above(
      "free block turned 30 degrees: linear FEM's deviation from the rigid "
      "motion (mm)",
      linear_deviation,
      1.);
  }
  {
    Scene scene;
    softface_tests::make_cube_scene(scene, 3000);
    const Vector<double> prescribed =
      softface_tests::move_bone(scene, Point<3>(0, 0, 0), 30.);
    Models::LinearFEM linear;
    linear.set_solver("direct", 0.);
    linear.setup(scene);
    Vector<double> u_linear;
    linear.solve(prescribed, u_linear);
    for (const std::string law : {"neo-hooke", "linear"})
      {
        Models::NonlinearFEM model;
        model.set_options(law, "direct");
        model.setup(scene);
        Vector<double> u;
        model.solve(prescribed, u);
        const double difference =
          softface_tests::relative_difference(u, u_linear);
        const std::string name = "held bone rotated 30 degrees, " + law;
        if (law == "linear")
          {
            softface_tests::check_below(name +
                                          ": relative difference to linear "
                                          "FEM",
                                        difference,
                                        1e-9);
            softface_tests::check_below(name + ": Newton iterations",
                                        model.report().newton_iterations,
                                        2);
          }
        else
          softface_tests::check_above(
            name + ": relative difference to linear FEM", difference, 1e-2);
      }
  }
}

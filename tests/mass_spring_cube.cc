// The mass spring model on the cube (8k tetrahedra): the 6 mm lift converges
// (every pending step below the threshold, no inverted tetrahedron, with and
// without the inversion guard, to the same answer); a rigid
// motion of every join point (30 degrees about (1,1,0) and a shift) moves the
// free points by the same rigid motion, which no linear model can do; and the
// seed's largest motion (16.7 mm) and 25 mm stay finite and either converge
// or stop with a message stating the pending step and the inverted
// tetrahedra (springs alone let the tissue above the bone collapse).

#include <softface/core/error.h>
#include <softface/models/mass_spring.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(mass_spring_cube)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 8000);

  {
    Models::MassSpring msm, guarded;
    guarded.set_prevent_inversion(true);
    msm.setup(scene);
    guarded.setup(scene);
    Vector<double> u, u_guarded;
    msm.solve(softface_tests::move_bone(scene, Point<3>(0, 0, 6)), u);
    guarded.solve(softface_tests::move_bone(scene, Point<3>(0, 0, 6)),
                  u_guarded);
    softface_tests::check(softface_tests::relative_difference(u_guarded, u) <
                            1e-12,
                          "6 mm: the guard changes nothing where nothing "
                          "inverts");
    deallog << "6 mm: " << msm.report().load_steps << " load steps"
            << std::endl;
    softface_tests::check(msm.report().max_step <= 1e-3,
                          "6 mm: every pending step below 0.001 mm");
    softface_tests::check(msm.report().inverted_tetrahedra == 0,
                          "6 mm: no inverted tetrahedron");
  }

  {
    const RigidMotion motion(Point<3>(2, -1, 3),
                             Point<3>(1, 1, 0),
                             30.,
                             Point<3>(40, 40, 40));
    Planning          planning;
    planning.set_motion(0, motion);
    planning.set_motion(1, motion);
    Models::MassSpring msm;
    msm.set_stop_threshold(1e-6);
    msm.setup(scene);
    Vector<double> u;
    msm.solve(planning.prescribed_displacement(scene), u);
    double      deviation = 0.;
    const auto &vertices  = scene.triangulation.get_vertices();
    for (unsigned int v = 0; v < vertices.size(); ++v)
      for (unsigned int c = 0; c < 3; ++c)
        deviation = std::max(deviation,
                             std::abs(u[scene.vertex_dofs()[v][c]] -
                                      motion.displacement(vertices[v])[c]));
    softface_tests::check(deviation < 1e-3,
                          "rigid motion of the join points moves the free "
                          "points rigidly (1e-3 mm)");
  }

  for (const double lift : {16.7, 25.})
    {
      Models::MassSpring msm;
      msm.set_prevent_inversion(true);
      msm.setup(scene);
      Vector<double> u;
      bool           converged = true, clear_message = true;
      try
        {
          msm.solve(softface_tests::move_bone(scene, Point<3>(0, 0, lift)), u);
        }
      catch (const Error &e)
        {
          converged = false;
          clear_message =
            std::string(e.what()).find("pending step") != std::string::npos;
        }
      const std::string name = softface_tests::rounded(lift) + " mm";
      deallog << name << ": " << (converged ? "converged" : "stopped")
              << std::endl;
      softface_tests::check(!converged || (std::isfinite(u.l2_norm()) &&
                                           u.linfty_norm() < 2 * lift),
                            name + ": finite displacement");
      softface_tests::check(clear_message,
                            name + ": converged or stopped with the pending "
                                   "step stated");
    }
}

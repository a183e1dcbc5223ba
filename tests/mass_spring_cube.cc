// The mass spring model on the cube (8k tetrahedra): the 6 mm lift converges
// (every pending step below the threshold, no inverted tetrahedron, with and
// without the inversion guard, to the same answer); a rigid
// motion of every join point (30 degrees about (1,1,0) and a shift) moves the
// free points by the same rigid motion, which no linear model can do; and the
// largest motion of Mollemans et al. 2007 (16.7 mm) and 25 mm stay finite and
// either converge or stop with a message stating the pending step and the
// inverted tetrahedra (springs alone let the tissue above the bone collapse).

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
    softface_tests::check_below(
      "6 mm: relative difference made by the inversion guard",
      softface_tests::relative_difference(u_guarded, u),
      1e-12);
    softface_tests::print("6 mm: load steps", msm.report().load_steps);
    softface_tests::print("6 mm: sweeps", msm.report().sweeps);
    softface_tests::check_below("6 mm: largest pending step (mm)",
                                msm.report().max_step,
                                1e-3);
    softface_tests::check_equal("6 mm: inverted tetrahedra",
                                msm.report().inverted_tetrahedra,
                                0);
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
    softface_tests::check_below(
      "rigid motion of every join point: largest deviation of a free point "
      "from that motion (mm)",
      deviation,
      1e-3);
  }

  for (const double lift : {16.7, 25.})
    {
      Models::MassSpring msm;
      msm.set_prevent_inversion(true);
      msm.setup(scene);
      Vector<double> u;
      std::string    message;
      try
        {
          msm.solve(softface_tests::move_bone(scene, Point<3>(0, 0, lift)), u);
        }
      catch (const Error &e)
        {
          message = e.what();
        }
      const std::string name = softface_tests::rounded(lift) + " mm";
      if (message.empty())
        {
          softface_tests::check_below(name + ": max |u| / lift",
                                      u.linfty_norm() / lift,
                                      2.);
          softface_tests::print(name + ": largest pending step (mm)",
                                msm.report().max_step);
        }
      else
        {
          deallog << name << ": stopped: " << message << std::endl;
          softface_tests::check_equal(name + ": the message states the pending "
                                             "step",
                                      message.find("pending step") !=
                                        std::string::npos,
                                      1);
        }
    }
}

// A phantom patient through the whole simulator (Mollemans et al. 2007,
// Sec. 3.1-3.3, end to end): CT -> labels -> surfaces -> bone parts -> mesh ->
// join points -> all four models (tests/run_patient.prm). The counts are
// printed and checked against ranges (another CGAL may mesh differently). Every
// model runs; its join points move exactly as planned, its free points by a few
// millimetres; the converged mass tensor model equals linear FEM to 1e-6 mm on
// the patient's mesh (it solves the same equations); nonlinear FEM and the mass
// spring model stay within a millimetre or two of it at these motions.

#include <softface/core/planning.h>
#include <softface/patient/image_io.h>
#include <softface/patient/planning_recovery.h>

#include "run_scene.h"

SOFTFACE_TEST(run_patient)
{
  using namespace softface;
  Simulator simulator;
  softface_tests::run_patient_scene(simulator, "run_patient.prm", 20);
  const Scene &scene = simulator.scene();

  std::map<std::string, const Report::ModelRun *> run_of;
  for (const auto &run : simulator.runs())
    {
      softface_tests::check_equal(run.model + ": failed", run.failed, 0);
      run_of[run.model] = &run;
    }
  softface_tests::check_equal("models run", run_of.size(), 4);
  // Join points where the plan puts them; the free tissue's largest motion
  // is the models' own answer (the lips may move more than the 5 mm of the
  // mandible, but not four times as much).
  const Vector<double> planned =
    simulator.plannings().plans.at(0).planning.prescribed_displacement(scene);
  for (const auto &[name, run] : run_of)
    {
      const auto motion =
        softface_tests::join_and_free_motion(scene, run->displacement, planned);
      softface_tests::check_below(name +
                                    ": join points, max |u - planned| (mm)",
                                  motion.join_error,
                                  1e-9);
      softface_tests::check_within(name + ": free points, max |u| (mm)",
                                   motion.free_largest,
                                   0.5,
                                   20.);
    }
  const auto &mtm = *run_of.at("mass tensor");
  softface_tests::check_below("max |u_mass tensor - u_linear fem| (mm)",
                              mtm.difference.max,
                              1e-6);
  softface_tests::check_within("max |u_nonlinear fem - u_linear fem| (mm)",
                               run_of.at("nonlinear fem")->difference.max,
                               0.,
                               2.);
  softface_tests::check_within("max |u_mass spring - u_linear fem| (mm)",
                               run_of.at("mass spring")->difference.max,
                               0.,
                               5.);

  // Planning from a post-operative skull made with the planned motions.
  using namespace softface::Patient;
  const auto parts = bone_part_surfaces(
    read_labels("output/run_patient/patient/bone_parts.nii.gz"), 3);
  std::vector<RigidTransform> truth(3), rough(3);
  truth[1].translation                 = {{0., -3., 0.}};
  truth[2].translation                 = {{0., -5., 0.}};
  const TriangleSurface post_operative = moved_skull(parts, truth);
  // The cranium is not planned to move (its start is the truth: a nearly
  // spherical part does not fix its rotation by ICP); the moved parts start
  // from a rough plan.
  rough[0] = truth[0];
  for (unsigned int s = 1; s < 3; ++s)
    rough[s] = RigidTransform::from_planning({{2., 1., -2.}},
                                             {{0., 1., 1.}},
                                             3.,
                                             {{0., -60., -20.}})
                 .after(truth[s]);
  const auto recovered =
    recover_motions(parts, post_operative, rough, IcpParameters());
  for (unsigned int s = 0; s < 3; ++s)
    {
      double largest = 0.;
      for (const auto &x : parts[s].points)
        {
          const Vec3 a = recovered[s].transform(x), b = truth[s](x);
          largest = std::max(largest,
                             std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
        }
      softface_tests::check_below(scene.segments[s].name +
                                    ": recovered motion error (mm)",
                                  largest,
                                  0.05);
    }
  const std::string section =
    planning_section({"cranium", "maxilla", "mandible"}, recovered, parts);
  ParameterHandler prm;
  Planning::declare_parameters(prm, {"maxilla", "mandible"});
  prm.parse_input_from_string(section);
  prm.enter_subsection("Planning");
  deallog << "Moved segments = " << prm.get("Moved segments") << std::endl;
  for (const std::string name : {"maxilla", "mandible"})
    {
      prm.enter_subsection("Motion " + name);
      const auto t = Utilities::string_to_double(
        Utilities::split_string_list(prm.get("Translation")));
      // To 0.001 mm, so that round-off prints as 0.
      const auto mm = [](const double x) {
        return softface_tests::rounded(std::round(x * 1000.) / 1000. + 0., 6);
      };
      deallog << name << ": translation " << mm(t[0]) << ", " << mm(t[1])
              << ", " << mm(t[2]) << std::endl;
      prm.leave_subsection();
    }
  prm.leave_subsection();
}

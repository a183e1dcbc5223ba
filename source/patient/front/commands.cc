// The patient subcommands (softface
// phantom|segment|mesh|postop|plan|register|preview SCENE.prm): the patient
// stages of a scene run on their own, for a user who checks each stage's
// files (or the preview's pictures) before meshing or planning.

#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/planning.h>
#include <softface/core/scene.h>
#include <softface/core/vec3_parameter.h>
#include <softface/patient/backend.h>
#include <softface/patient/commands.h>

#include <filesystem>
#include <iomanip>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      // The stages postop and plan: the scene's planning as rigid
      // transforms of the bone parts.
      int
      plan_from_skull(ParameterHandler               &prm,
                      const std::string              &filename,
                      const std::string              &stage,
                      const PatientParameters        &patient,
                      const std::vector<SegmentSeed> &seeds,
                      std::ostream                   &out)
      {
        Scene scene;
        scene.parse_parameters(
          prm,
          std::filesystem::path(filename).parent_path().string(),
          patient.work_directory,
          &out);
        Planning planning;
        planning.parse_parameters(prm, scene);

        // The scene's planning as rigid transforms x -> R x + t.
        std::vector<RigidTransform> planned;
        for (unsigned int s = 0; s < scene.segments.size(); ++s)
          {
            const RigidMotion motion = planning.motion(s);
            const Point<3>    t      = motion(Point<3>());
            RigidTransform    transform;
            for (unsigned int d = 0; d < 3; ++d)
              {
                transform.translation[d] = t[d];
                Point<3> e;
                e[d]                 = 1.;
                const Point<3> image = motion(e);
                for (unsigned int r = 0; r < 3; ++r)
                  transform.rotation[3 * r + d] = image[r] - t[r];
              }
            planned.push_back(transform);
          }
        return backend().skull_stage(patient, seeds, planned, stage, out);
      }
    } // namespace

    int
    run_command(ParameterHandler  &prm,
                const std::string &filename,
                const std::string &stage,
                const std::string &output_directory,
                std::ostream      &out)
    {
      const std::string input_directory =
        std::filesystem::path(filename).parent_path().string();

      PatientParameters        patient;
      std::vector<SegmentSeed> seeds;
      prm.enter_subsection("Scene");
      if (prm.get("Mesh source") != "patient")
        throw Error(filename + ": 'softface " + stage +
                    "' runs the patient stages of a scene with 'Scene/Mesh "
                    "source = patient'.");
      patient.parse_parameters(prm,
                               input_directory,
                               output_directory + "/patient");
      // Errors about seeds, cuts and parts point at the preview of this
      // very file.
      patient.osteotomy.scene_file = filename;
      for (const std::string &name :
           Utilities::split_string_list(prm.get("Bone segments")))
        {
          prm.enter_subsection("Segment " + name);
          const std::string point = prm.get("Seed point");
          prm.leave_subsection();
          if (point.empty())
            throw Error("Scene/Segment " + name +
                        ": a patient scene's segment needs a 'Seed point' "
                        "'x, y, z' in its bone.");
          seeds.push_back(
            {name, parse_vec3(point, "Scene/Segment " + name + "/Seed point")});
        }
      prm.leave_subsection();

      out << "softface " << stage << ": " << filename << std::endl;
      Timer wall;
      if (stage == "register")
        {
          backend().register_post_operative(patient, output_directory, out);
          return 0;
        }
      if (stage == "preview")
        return backend().preview(patient, seeds, out);
      if (stage == "postop" || stage == "plan")
        return plan_from_skull(prm, filename, stage, patient, seeds, out);
      const auto model = backend().build_patient_model(
        patient,
        seeds,
        stage == "phantom" ?
          Stage::phantom :
          (stage == "segment" ? Stage::segmentation : Stage::mesh),
        out);
      for (const auto &[name, value] : model.figures)
        out << "  " << name << ": " << value << '\n';
      out << "Files in " << patient.work_directory << "/ (wall time "
          << std::fixed << std::setprecision(1) << wall.wall_time() << " s)"
          << std::endl;
      return 0;
    }
  } // namespace Patient
} // namespace softface

// The mesh source 'patient' (mesh_sources): the patient pipeline (subsection
// Scene/Patient: CT or phantom -> segmentation -> osteotomy -> mesh), whose
// bone parts become the segments named by their 'Seed point'.

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/mesh_source.h>
#include <softface/core/on_rank_0.h>
#include <softface/core/scene.h>
#include <softface/io/mesh_reader.h>
#include <softface/patient/backend.h>

#include <filesystem>
#include <sstream>

namespace softface
{
  namespace MeshSources
  {
    class PatientPipeline : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler               &prm,
                         const std::vector<std::string> &cut_names)
      {
        Patient::PatientParameters::declare_parameters(prm, cut_names);
      }

      /// The names of the osteotomy's cuts (each has a subsection).
      static std::vector<std::string>
      names_from_first_pass(ParameterHandler &prm)
      {
        return Patient::PatientParameters::cut_names(prm);
      }

      void
      parse_parameters(ParameterHandler  &prm,
                       const std::string &input_directory,
                       const std::string &work_directory) override
      {
        parameters.parse_parameters(prm, input_directory, work_directory);
      }

      MadeMesh
      make_mesh(std::vector<BoneSegment> &segments,
                Triangulation<3>         &triangulation,
                MPI_Comm                  mesh_readers,
                std::ostream             *log) override;

    private:
      Patient::PatientParameters parameters;
    };


    MadeMesh
    PatientPipeline::make_mesh(std::vector<BoneSegment> &segments,
                               Triangulation<3>         &triangulation,
                               const MPI_Comm            mesh_readers,
                               std::ostream             *log)
    {
      // Each segment's join points are the faces touching its bone part.
      std::vector<Patient::SegmentSeed> seeds;
      for (const auto &segment : segments)
        {
          if (segment.seed_point.size() != 3)
            throw Error("Scene/Segment " + segment.name +
                        ": a patient scene's segment needs a 'Seed point' "
                        "in its bone.");
          seeds.push_back({segment.name,
                           {{segment.seed_point[0],
                             segment.seed_point[1],
                             segment.seed_point[2]}}});
        }
      // On several MPI ranks rank 0 alone runs the pipeline, which writes
      // its stages into the work directory (and Mesh_3 does not make the
      // same mesh twice); the others read the mesh it wrote, which must be
      // on a file system they all see.
      const MPI_Comm world       = MPI_COMM_WORLD;
      const bool     several     = Utilities::MPI::n_mpi_processes(world) > 1;
      const bool     holds_cells = mesh_readers != MPI_COMM_NULL;
      Patient::PatientModel model;
      std::string           read_from; // absolute: the ranks' folders differ
      on_rank_0(world, [&]() {
        std::ostringstream quiet;
        model =
          Patient::backend().build_patient_model(parameters,
                                                 seeds,
                                                 Patient::Stage::mesh,
                                                 log != nullptr ? *log : quiet);
        read_from = std::filesystem::absolute(model.mesh_file).string();
      });
      if (several)
        {
          model.mesh_file = Utilities::MPI::broadcast(world, model.mesh_file);
          read_from       = Utilities::MPI::broadcast(world, read_from);
          model.segment_boundary_ids =
            Utilities::MPI::broadcast(world, model.segment_boundary_ids);
          model.figures = Utilities::MPI::broadcast(world, model.figures);
        }
      MadeMesh made;
      made.figures = model.figures;
      if (holds_cells)
        made.cell_name =
          Mesh::read_file_on_every_rank(mesh_readers, read_from, triangulation);
      if (several && holds_cells)
        {
          // An older mesh of the same name on a rank's own disk would pass
          // silently: the ranks compare what they read.
          double checksum = triangulation.n_active_cells();
          for (const auto &vertex : triangulation.get_vertices())
            checksum += vertex[0] + 2. * vertex[1] + 3. * vertex[2];
          const bool differs =
            checksum != Utilities::MPI::broadcast(mesh_readers, checksum);
          if (Utilities::MPI::max(int(differs), mesh_readers) != 0)
            throw Error("Scene: the ranks read different meshes from '" +
                        read_from +
                        "', which rank 0's patient pipeline wrote: the "
                        "patient's work directory must be on a file "
                        "system every rank sees.");
        }
      made.resolve_shared_join_points = true;
      for (unsigned int s = 0; s < segments.size(); ++s)
        for (const auto id : model.segment_boundary_ids[s])
          segments[s].boundary_ids.insert(id);
      made.description = "'" + model.mesh_file + "' (patient)";
      return made;
    }

    SOFTFACE_REGISTER_MESH_SOURCE(
      PatientPipeline,
      "patient",
      "runs the patient pipeline (subsection Patient: CT or phantom -> "
      "segmentation -> osteotomy -> mesh); its segments are found by their "
      "'Seed point'")
  } // namespace MeshSources
} // namespace softface

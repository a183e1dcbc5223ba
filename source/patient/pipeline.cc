// The patient pipeline (patient; Mollemans et al. 2007, Sec. 3.1-3.3): the
// stages CT (phantom or file) -> segmentation and surfaces -> bone parts and
// the tetrahedral mesh, each leaving files the next reads, skipped when its
// inputs have not changed. Scene calls it for 'Mesh source = patient'; the
// subcommands phantom, segment and mesh stop after their stage. At the end,
// the subcommand register (Mollemans et al. 2007, 3.5.1): a post-operative
// CT rigidly registered to the pre-operative one, and the post-operative
// surfaces carried into the pre-operative frame with it.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/patient/build_stamp.h>
#include <softface/patient/image_io.h>
#include <softface/patient/pipeline.h>
#include <softface/patient/registration.h>
#include <softface/patient/surface.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <tuple>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      namespace fs = std::filesystem;

      // What a stage's output depends on, as text (the build and library
      // versions of build_stamp(), then the stage's inputs and parameters):
      // a stage is skipped when its stamp file holds the same.
      template <typename... T>
      std::string
      stamp_of(const T &...items)
      {
        std::ostringstream s;
        s << std::setprecision(17);
        ((s << items << '\n'), ...);
        return s.str();
      }

      // A segmentation threshold in a stamp: its number, or 'auto', whose
      // value the CT (earlier in the stamp) and the smoothing decide. A
      // number is written as stamp_of() writes it, so that the stamps of
      // numbers stay what they were.
      std::string
      threshold_stamp(const double value, const bool automatic)
      {
        if (automatic)
          return "auto";
        std::ostringstream s;
        s << std::setprecision(17) << value;
        return s.str();
      }

      std::string
      file_stamp(const std::string &file)
      {
        std::error_code ec;
        const auto size = fs::is_directory(file) ? 0 : fs::file_size(file, ec);
        const auto time = fs::last_write_time(file, ec);
        return file + " " + std::to_string(size) + " " +
               std::to_string(time.time_since_epoch().count());
      }

      bool
      up_to_date(const fs::path                 &stamp_file,
                 const std::string              &stamp,
                 const std::vector<std::string> &outputs)
      {
        std::ifstream      in(stamp_file);
        std::ostringstream old;
        old << in.rdbuf();
        if (!in || old.str() != stamp)
          return false;
        for (const auto &o : outputs)
          if (!fs::exists(o))
            return false;
        return true;
      }

      // Outputs appear under their final names only when complete.
      template <typename Write>
      void
      write_atomically(const fs::path &file, Write &&write)
      {
        const fs::path partial =
          file.parent_path() / (".partial." + file.filename().string());
        write(partial.string());
        fs::rename(partial, file);
      }

      class StageClock
      {
      public:
        double
        seconds() const
        {
          return std::chrono::duration<double>(
                   std::chrono::steady_clock::now() - start)
            .count();
        }

      private:
        std::chrono::steady_clock::time_point start =
          std::chrono::steady_clock::now();
      };

      std::string
      number(const double x, const int digits = 4)
      {
        std::ostringstream s;
        s << std::setprecision(digits) << x;
        return s.str();
      }

      double
      peak_memory_mb()
      {
        dealii::Utilities::System::MemoryStats stats;
        dealii::Utilities::System::get_memory_stats(stats);
        return stats.VmHWM / 1024.;
      }

      /**
       * One build of a patient model, stage by stage: each stage reuses
       * its files in the work folder while its stamp (the build of
       * softface and every input the stage reads, its predecessors'
       * included) is unchanged, and adds its figures to the model.
       */
      class Stages
      {
      public:
        Stages(const PatientParameters        &prm,
               const std::vector<SegmentSeed> &segments,
               std::ostream                   &log)
            : prm(prm)
            , segments(segments)
            , log(log)
            , work(prm.work_directory)
        {
          fs::create_directories(work);
        }

        /// 1. The CT: the phantom's acquisition or the patient's file.
        void
        ct_stage();
        /// 2. Labels and the dense skin and skull surfaces.
        void
        segmentation_stage();
        /// 3. Bone parts and the tetrahedral mesh of the region of
        /// interest.
        void
        mesh_stage();
        /// The segments' boundary ids, the peak memory; the model.
        PatientModel
        finish();

        PatientModel model;

      private:
        /// What the mesh stage reads: its stamp.
        std::string
        mesh_stamp() const;

        void
        figure(const std::string &name, const std::string &value)
        {
          model.figures.emplace_back(name, value);
        }

        // A stage's figures are kept beside its files, so that a reused
        // stage reports what it made.
        void
        save_figures(const std::string &stage, const std::size_t first)
        {
          std::ofstream out(work / (stage + ".figures"));
          for (std::size_t i = first; i < model.figures.size(); ++i)
            out << model.figures[i].first << '\t' << model.figures[i].second
                << '\n';
        }

        void
        load_figures(const std::string &stage)
        {
          std::ifstream in(work / (stage + ".figures"));
          std::string   line;
          while (std::getline(in, line))
            {
              const auto tab = line.find('\t');
              if (tab != std::string::npos)
                model.figures.emplace_back(line.substr(0, tab),
                                           line.substr(tab + 1));
            }
        }

        std::string
        file(const std::string &name) const
        {
          return (work / name).string();
        }

        const PatientParameters        &prm;
        const std::vector<SegmentSeed> &segments;
        std::ostream                   &log;
        const fs::path                  work;
        StageClock                      clock;
        CTVolume                        ct;
        std::string                     ct_stamp;
        LabelVolume                     labels;
        std::string                     labels_stamp;
      };

      void
      Stages::ct_stage()
      {
        // 1. The CT: the phantom's acquisition, or the patient's file. Every
        // stamp starts with the build that makes the stages (which changes
        // with the phantom's anatomy and the mesher's code alike).
        const std::string build = build_stamp();
        clock                   = StageClock();
        if (prm.ct_volume.empty())
          {
            const auto &p = prm.phantom;
            ct_stamp      = build + stamp_of("phantom",
                                        p.voxel_size,
                                        p.field_of_view[0],
                                        p.field_of_view[1],
                                        p.field_of_view[2],
                                        p.centre[0],
                                        p.centre[1],
                                        p.centre[2],
                                        p.face_width,
                                        p.face_height,
                                        p.soft_tissue_thickness,
                                        p.mandible_length,
                                        p.mandible_angle,
                                        p.profile,
                                        p.jaw_discrepancy,
                                        p.noise,
                                        p.blur,
                                        p.metal_streaks,
                                        p.closed_mouth,
                                        p.seed);
            if (prm.reuse &&
                up_to_date(work / "ct.stamp",
                           ct_stamp,
                           {file("ct.nii.gz"), file("truth_labels.nii.gz")}))
              {
                ct = read_ct(file("ct.nii.gz"));
                load_figures("ct");
                log << "    phantom CT: reused " << file("ct.nii.gz")
                    << std::endl;
              }
            else
              {
                LabelVolume truth;
                Phantom(p).acquire(ct, truth);
                write_atomically(work / "ct.nii.gz", [&](const std::string &f) {
                  write_volume(ct, f);
                });
                write_atomically(work / "truth_labels.nii.gz",
                                 [&](const std::string &f) {
                                   write_volume(truth, f);
                                 });
                std::ofstream(work / "ct.stamp") << ct_stamp;
                log << "    phantom CT: " << ct.size[0] << " x " << ct.size[1]
                    << " x " << ct.size[2] << " voxels of " << p.voxel_size
                    << " mm (" << std::fixed << std::setprecision(1)
                    << clock.seconds() << " s)" << std::defaultfloat
                    << std::endl;
                figure("phantom s", number(clock.seconds()));
                save_figures("ct", model.figures.size() - 1);
              }
          }
        else
          {
            try
              {
                ct = read_ct(prm.ct_volume);
              }
            catch (const Error &e)
              {
                throw Error(std::string("Scene/Patient/CT volume: ") +
                            e.what());
              }
            ct_stamp = build + stamp_of("file", file_stamp(prm.ct_volume));
            log << "    CT " << prm.ct_volume << ": " << ct.size[0] << " x "
                << ct.size[1] << " x " << ct.size[2] << " voxels ("
                << std::fixed << std::setprecision(1) << clock.seconds()
                << " s)" << std::defaultfloat << std::endl;
            figure("CT read s", number(clock.seconds()));
          }
        figure("CT voxels",
               std::to_string(ct.size[0]) + " x " + std::to_string(ct.size[1]) +
                 " x " + std::to_string(ct.size[2]));
        figure("voxel mm", number(ct.spacing[0]));
      }

      void
      Stages::segmentation_stage()
      {
        // 2. Labels and the dense skin and skull surfaces.
        clock         = StageClock();
        const auto &s = prm.segmentation;
        labels_stamp =
          ct_stamp +
          stamp_of("segmentation",
                   prm.label_volume.empty() ? std::string("softface") :
                                              file_stamp(prm.label_volume),
                   s.smoothing,
                   threshold_stamp(s.body_threshold, s.auto_body_threshold),
                   threshold_stamp(s.bone_threshold, s.auto_bone_threshold),
                   threshold_stamp(s.fat_threshold, s.auto_fat_threshold),
                   s.skin_thickness,
                   s.min_bone_volume);
        // The thresholds used, beside the labels: for the reader, and for a
        // reused stage's report.
        const fs::path           thresholds_file = work / "thresholds.txt";
        std::vector<std::string> outputs         = {file("labels.nii.gz"),
                                                    file("skin.vtp"),
                                                    file("skull.vtp")};
        if (prm.label_volume.empty())
          outputs.push_back(thresholds_file.string());
        if (prm.reuse &&
            up_to_date(work / "labels.stamp", labels_stamp, outputs))
          {
            labels = read_labels(file("labels.nii.gz"));
            load_figures("labels");
            log << "    segmentation: reused " << file("labels.nii.gz")
                << std::endl;
            if (prm.label_volume.empty())
              {
                std::ifstream in(thresholds_file);
                std::string   line;
                std::getline(in, line);
                log << "    " << line << std::endl;
              }
          }
        else
          {
            Volume<float> body_field, bone_field;
            double body_level = s.body_threshold, bone_level = s.bone_threshold;
            std::string                                        thresholds;
            std::vector<std::tuple<std::string, double, bool>> used;
            if (prm.label_volume.empty())
              {
                auto result =
                  segment(ct,
                          s,
                          prm.ct_volume.empty() ? std::string("phantom") :
                                                  prm.ct_volume);
                labels     = std::move(result.labels);
                body_field = std::move(result.smoothed);
                // The surfaces at the thresholds the labels were made with.
                body_level = result.body_threshold;
                bone_level = result.bone_threshold;
                thresholds = "thresholds: " + describe_thresholds(s, result);
                used       = {{{"body threshold",
                                result.body_threshold,
                                s.auto_body_threshold},
                               {"bone threshold",
                                result.bone_threshold,
                                s.auto_bone_threshold},
                               {"fat threshold",
                                result.fat_threshold,
                                s.auto_fat_threshold}}};
              }
            else
              {
                try
                  {
                    labels = read_labels(prm.label_volume);
                  }
                catch (const Error &e)
                  {
                    throw Error(std::string("Scene/Patient/Label volume: ") +
                                e.what());
                  }
                if (labels.size != ct.size)
                  throw Error("Scene/Patient/Label volume '" +
                              prm.label_volume +
                              "' does not have the CT's size.");
                // Surfaces of one's own labels: the masks' half-way levels.
                body_field.reinit_like(labels);
                for (std::size_t v = 0; v < labels.n_voxels(); ++v)
                  body_field.values[v] = (labels.values[v] != outside_body);
                body_level = 0.5;
              }
            if (prm.label_volume.empty())
              bone_field = body_field;
            else
              {
                bone_field.reinit_like(labels);
                for (std::size_t v = 0; v < labels.n_voxels(); ++v)
                  bone_field.values[v] = (labels.values[v] == bone_tissue);
                bone_level = 0.5;
              }
            const TriangleSurface skin =
              iso_surface(body_field, body_level, true);
            const TriangleSurface skull =
              iso_surface(bone_field, bone_level, false, 200);
            write_atomically(work / "labels.nii.gz", [&](const std::string &f) {
              write_volume(labels, f);
            });
            for (const std::string ext : {".ply", ".vtp"})
              {
                write_atomically(work / ("skin" + ext),
                                 [&](const std::string &f) {
                                   write_surface(skin, f);
                                 });
                write_atomically(work / ("skull" + ext),
                                 [&](const std::string &f) {
                                   write_surface(skull, f);
                                 });
              }
            if (prm.label_volume.empty())
              write_atomically(thresholds_file, [&](const std::string &f) {
                std::ofstream out(f);
                out << thresholds << '\n';
                if (!out)
                  throw Error("Cannot write " + f + ".");
              });
            std::ofstream(work / "labels.stamp") << labels_stamp;
            const std::size_t first = model.figures.size();
            for (const auto &[name, value, automatic] : used)
              figure(name, number(value, 6) + (automatic ? " auto" : ""));
            figure("skin vertices", std::to_string(skin.points.size()));
            figure("skull vertices", std::to_string(skull.points.size()));
            figure("segmentation s", number(clock.seconds()));
            save_figures("labels", first);
            if (prm.label_volume.empty())
              log << "    " << thresholds << std::endl;
            log << "    segmentation: skin " << skin.points.size()
                << " vertices, skull " << skull.points.size() << " vertices ("
                << std::fixed << std::setprecision(1) << clock.seconds()
                << " s)" << std::defaultfloat << std::endl;
          }
        {
          std::vector<std::size_t> count(6, 0);
          for (const auto l : labels.values)
            if (l < 6)
              ++count[l];
          const char *names[6] = {
            "", "skin", "fat", "muscle", "bone", "internal"};
          for (unsigned int l = 1; l < 6; ++l)
            figure(std::string(names[l]) + " cm3",
                   number(count[l] * labels.voxel_volume() / 1000.));
        }
      }

      std::string
      Stages::mesh_stamp() const
      {
        std::ostringstream inputs;
        inputs << std::setprecision(17) << "mesh\n";
        for (const auto &seed : segments)
          inputs << seed.name << ' ' << seed.point[0] << ' ' << seed.point[1]
                 << ' ' << seed.point[2] << '\n';
        for (const auto &cut : prm.osteotomy.cuts)
          {
            inputs << cut.name << ' ' << cut.type;
            for (const auto &v :
                 {cut.point, cut.normal, cut.sweep, cut.box_min, cut.box_max})
              inputs << ' ' << v[0] << ' ' << v[1] << ' ' << v[2];
            for (const auto &v : cut.polyline)
              inputs << ' ' << v[0] << ' ' << v[1] << ' ' << v[2];
            // Only a margin of the cut's own, so that a cut without one
            // leaves the stamp as it is.
            if (cut.detached_margin != prm.osteotomy.detached_margin)
              inputs << " margin " << cut.detached_margin;
            inputs << '\n';
          }
        inputs << prm.osteotomy.kerf << ' ' << prm.osteotomy.detached_margin
               << ' ' << prm.osteotomy.min_part_volume << '\n';
        for (const auto &v : {prm.roi.box_min, prm.roi.box_max})
          inputs << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
        for (const auto &[p, n] : prm.roi.planes)
          inputs << p[0] << ' ' << p[1] << ' ' << p[2] << ' ' << n[0] << ' '
                 << n[1] << ' ' << n[2] << '\n';
        const auto &m = prm.mesh;
        inputs << m.cell_size << ' ' << m.target_n_tetrahedra << ' '
               << m.facet_distance << ' ' << m.facet_angle << ' '
               << m.radius_edge_ratio << ' ' << m.sliver_bound << ' '
               << m.conforming_interfaces << ' ' << m.seed << '\n';
        return labels_stamp + inputs.str();
      }

      void
      Stages::mesh_stage()
      {
        // 3. Bone parts and the tetrahedral mesh of the region of interest.
        clock                        = StageClock();
        const std::string mesh_stamp = this->mesh_stamp();
        model.mesh_file              = file("mesh.vtu");
        std::vector<std::size_t> contact_faces(segments.size(), 0);
        if (prm.reuse &&
            up_to_date(work / "mesh.stamp",
                       mesh_stamp,
                       {file("mesh.vtu"), file("bone_parts.nii.gz")}))
          {
            load_figures("mesh");
            log << "    mesh: reused " << model.mesh_file << std::endl;
          }
        else
          {
            const LabelVolume parts =
              split_bone(labels, bone_tissue, prm.osteotomy, segments);
            const double    split_seconds = clock.seconds();
            TetrahedralMesh mesh;
            try
              {
                mesh = make_tetrahedral_mesh(labels,
                                             {skin_tissue,
                                              fat_tissue,
                                              muscle_tissue},
                                             bone_tissue,
                                             parts,
                                             prm.roi,
                                             prm.mesh);
              }
            catch (const Error &)
              {
                throw;
              }
            catch (const std::exception &e)
              {
                throw Error(std::string("Mesh: CGAL could not mesh the soft "
                                        "tissue: ") +
                            e.what());
              }
            for (const auto id : mesh.boundary_ids)
              if (id >= first_bone_boundary_id &&
                  id - first_bone_boundary_id < segments.size())
                ++contact_faces[id - first_bone_boundary_id];
            for (unsigned int s = 0; s < segments.size(); ++s)
              if (contact_faces[s] == 0)
                throw Error("Segment '" + segments[s].name +
                            "': its bone part touches no soft tissue of the "
                            "mesh, so it would have no join point; move the "
                            "cuts or the region of interest, or drop the "
                            "segment." +
                            preview_hint(prm.osteotomy.scene_file));
            write_atomically(work / "bone_parts.nii.gz",
                             [&](const std::string &f) {
                               write_volume(parts, f);
                             });
            write_atomically(work / "mesh.msh",
                             [&](const std::string &f) { mesh.write_msh(f); });
            write_atomically(work / "mesh.vtu",
                             [&](const std::string &f) { mesh.write_vtu(f); });
            std::ofstream(work / "mesh.stamp") << mesh_stamp;

            const auto q = mesh.quality();
            // The segmented soft tissue the mesh stands for.
            std::size_t n_soft = 0;
            for (std::size_t k = 0; k < labels.size[2]; ++k)
              for (std::size_t j = 0; j < labels.size[1]; ++j)
                for (std::size_t i = 0; i < labels.size[0]; ++i)
                  {
                    const auto l = labels(i, j, k);
                    n_soft += (l == skin_tissue || l == fat_tissue ||
                               l == muscle_tissue) &&
                              prm.roi.contains(labels.point(i, j, k));
                  }
            const double      soft_volume = n_soft * labels.voxel_volume();
            const std::size_t first       = model.figures.size();
            figure("tetrahedra", std::to_string(mesh.cells.size()));
            figure("mesh vertices", std::to_string(mesh.points.size()));
            figure("min dihedral deg", number(q.min_dihedral_angle));
            figure("worst radius ratio", number(q.worst_radius_ratio));
            figure("sliver perturbation", mesh.perturbation_outcome);
            figure("sliver exudation", mesh.exudation_outcome);
            figure("mesh volume cm3", number(q.volume / 1000.));
            figure("soft tissue in region cm3", number(soft_volume / 1000.));
            figure("bone split s", number(split_seconds));
            figure("mesh s", number(clock.seconds() - split_seconds));
            for (unsigned int s = 0; s < segments.size(); ++s)
              figure("contact faces " + segments[s].name,
                     std::to_string(contact_faces[s]));
            save_figures("mesh", first);
            log << "    mesh: " << mesh.cells.size() << " tetrahedra, "
                << mesh.points.size() << " vertices, smallest dihedral angle "
                << number(q.min_dihedral_angle, 3) << " degrees, volume "
                << number(q.volume / 1000.) << " cm^3 of "
                << number(soft_volume / 1000.) << " cm^3 segmented ("
                << std::fixed << std::setprecision(1) << clock.seconds()
                << " s)" << std::defaultfloat << std::endl;
          }
      }

      PatientModel
      Stages::finish()
      {
        figure("peak memory MB", number(peak_memory_mb()));

        model.segment_boundary_ids.resize(segments.size());
        for (unsigned int s = 0; s < segments.size(); ++s)
          {
            model.segment_boundary_ids[s].push_back(first_bone_boundary_id + s);
            if (segments[s].name == prm.cut_held_by)
              model.segment_boundary_ids[s].push_back(cut_boundary_id);
          }
        if (!prm.cut_held_by.empty())
          {
            bool found = false;
            for (const auto &seed : segments)
              found |= seed.name == prm.cut_held_by;
            if (!found)
              throw Error("Scene/Patient/Cut held by: '" + prm.cut_held_by +
                          "' is not one of the scene's bone segments.");
          }
        return model;
      }
    } // namespace

    PatientModel
    build_patient_model(const PatientParameters        &prm,
                        const std::vector<SegmentSeed> &segments,
                        std::ostream                   &log)
    {
      return build_patient_model(prm, segments, Stage::mesh, log);
    }

    PatientModel
    build_patient_model(const PatientParameters        &prm,
                        const std::vector<SegmentSeed> &segments,
                        const Stage                     last_stage,
                        std::ostream                   &log)
    {
      Stages stages(prm, segments, log);
      stages.ct_stage();
      if (last_stage == Stage::phantom)
        return stages.model;
      stages.segmentation_stage();
      if (last_stage == Stage::segmentation)
        return stages.model;
      stages.mesh_stage();
      return stages.finish();
    }

    // Registration of a post-operative CT ('softface register').

    void
    register_post_operative(const PatientParameters &prm,
                            const std::string       &output_directory,
                            std::ostream            &out)
    {
      const auto       &stage = prm.registration;
      const std::string where = "Scene/Patient/Registration/";
      StageClock        clock;

      // What is missing or unreadable ends the run before the
      // pre-operative CT is made and the registration runs.
      if (stage.post_operative_ct.empty())
        throw Error(where +
                    "Post-operative CT: empty, but 'softface register' "
                    "needs the post-operative CT (a volume file or a DICOM "
                    "folder) to register to the pre-operative one" +
                    (prm.ct_volume.empty() ?
                       std::string(" (here the phantom's; softface makes no "
                                   "post-operative CT)") :
                       std::string(" ('CT volume')")) +
                    ".");
      CTVolume post;
      try
        {
          post = read_ct(stage.post_operative_ct);
        }
      catch (const Error &e)
        {
          throw Error(where + "Post-operative CT: " + e.what());
        }
      // Each surface under the name it is written with.
      std::vector<std::pair<std::string, TriangleSurface>> surfaces;
      std::set<std::string>                                names;
      for (const auto &file : stage.post_operative_surfaces)
        {
          const std::string name =
            fs::path(file).stem().string() + "_registered.ply";
          if (!names.insert(name).second)
            throw Error(where +
                        "Post-operative surfaces: two surfaces "
                        "would be written as " +
                        name + "; give them different names.");
          try
            {
              surfaces.emplace_back(name, read_surface(file));
            }
          catch (const Error &e)
            {
              throw Error(where + "Post-operative surfaces: " + e.what());
            }
        }

      // The pre-operative CT: the patient's file, or the phantom's.
      CTVolume pre;
      if (prm.ct_volume.empty())
        {
          build_patient_model(prm, {}, Stage::phantom, out);
          pre = read_ct((fs::path(prm.work_directory) / "ct.nii.gz").string());
        }
      else
        {
          try
            {
              pre = read_ct(prm.ct_volume);
            }
          catch (const Error &e)
            {
              throw Error(std::string("Scene/Patient/CT volume: ") + e.what());
            }
        }
      const auto size = [](const CTVolume &ct) {
        return std::to_string(ct.size[0]) + " x " + std::to_string(ct.size[1]) +
               " x " + std::to_string(ct.size[2]) + " voxels of " +
               number(ct.spacing[0]) + " x " + number(ct.spacing[1]) + " x " +
               number(ct.spacing[2]) + " mm";
      };
      out << "    pre-operative CT: " << size(pre) << '\n'
          << "    post-operative CT " << stage.post_operative_ct << ": "
          << size(post) << std::endl;

      StageClock               registration_clock;
      const RegistrationResult r =
        register_rigid(pre, post, stage.registration);
      const double registration_seconds = registration_clock.seconds();
      const auto  &s                    = r.subvolume;
      out << "    subvolume: " << r.subvolume_voxels[0] << " x "
          << r.subvolume_voxels[1] << " x " << r.subvolume_voxels[2]
          << " voxels, centres in [" << s.lower[0] << ", " << s.upper[0]
          << "] x [" << s.lower[1] << ", " << s.upper[1] << "] x ["
          << s.lower[2] << ", " << s.upper[2] << "] mm ("
          << (stage.registration.restriction ==
                  RegistrationParameters::Restriction::crop ?
                "cropped" :
                "masked")
          << ")\n";
      for (std::size_t l = 0; l < r.levels.size(); ++l)
        out << "    level " << l + 1 << " (shrink " << r.levels[l].shrink_factor
            << ", sigma " << r.levels[l].smoothing_sigma << " mm, first step "
            << number(r.levels[l].learning_rate)
            << "): " << r.levels[l].iterations << " iterations, metric "
            << number(r.levels[l].metric, 6) << " (" << r.levels[l].stop
            << ")\n";
      const auto &t    = r.post_to_pre.translation;
      const Vec3  axis = r.post_to_pre.axis();
      out << "  post-operative to pre-operative frame: rotation "
          << number(r.angle_degrees, 4) << " degrees about ("
          << number(axis[0], 3) << ", " << number(axis[1], 3) << ", "
          << number(axis[2], 3) << "), translation (" << number(t[0], 4) << ", "
          << number(t[1], 4) << ", " << number(t[2], 4) << ") mm, metric "
          << number(r.metric, 6) << " (" << std::fixed << std::setprecision(1)
          << registration_seconds << " s)" << std::defaultfloat << std::endl;

      // The files, each complete or not at all.
      const fs::path directory(output_directory);
      fs::create_directories(directory);
      write_atomically(directory / "registration.csv",
                       [&](const std::string &f) {
                         std::ofstream file(f);
                         file << registration_table(r);
                         if (!file)
                           throw Error("Cannot write " + f + ".");
                       });
      write_atomically(directory / "postop_ct_registered.nii.gz",
                       [&](const std::string &f) {
                         write_volume(resample(post, r.post_to_pre, pre), f);
                       });
      std::string files = "registration.csv, postop_ct_registered.nii.gz";
      for (const auto &[name, surface] : surfaces)
        {
          write_atomically(directory / name, [&](const std::string &f) {
            write_surface(transform_surface(surface, r.post_to_pre), f);
          });
          files += ", " + name;
        }
      out << "Files in " << output_directory << "/ (" << files << "; wall time "
          << std::fixed << std::setprecision(1) << clock.seconds() << " s)"
          << std::defaultfloat << std::endl;
    }
  } // namespace Patient
} // namespace softface

// The patient pipeline (patient, seed 3.1-3.3): its parameters and the stages
// CT (phantom or file) -> segmentation and surfaces -> bone parts and the
// tetrahedral mesh, each leaving files the next reads, skipped when its
// inputs have not changed. Scene calls it for 'Mesh source = patient'; the
// subcommands phantom, segment and mesh stop after their stage.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/patient/image_io.h>
#include <softface/patient/pipeline.h>
#include <softface/patient/surface.h>
#include <softface/patient/vec3_parameter.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      using dealii::ParameterHandler;
      namespace Patterns = dealii::Patterns;
      namespace fs       = std::filesystem;

      std::string
      resolve(const std::string &file, const std::string &directory)
      {
        if (file.empty() || fs::path(file).is_absolute() || directory.empty())
          return file;
        return (fs::path(directory) / file).string();
      }

      // What a stage's output depends on, as text: a stage is skipped when
      // its stamp file holds the same.
      template <typename... T>
      std::string
      stamp_of(const T &...items)
      {
        std::ostringstream s;
        s << std::setprecision(17);
        ((s << items << '\n'), ...);
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
    } // namespace

    void
    PatientParameters::declare_parameters(
      ParameterHandler               &prm,
      const std::vector<std::string> &cut_names)
    {
      prm.enter_subsection("Patient");
      prm.declare_entry("CT volume",
                        "",
                        Patterns::Anything(),
                        "The patient's CT: a volume file ITK reads (NIfTI "
                        ".nii/.nii.gz, NRRD, MetaImage) or a folder with a "
                        "DICOM series, in Hounsfield units. Empty: the phantom "
                        "of subsection Phantom. Relative to the parameter "
                        "file's folder.");
      prm.declare_entry("Label volume",
                        "",
                        Patterns::Anything(),
                        "A segmentation of one's own instead of softface's "
                        "(values 0 outside the body, 1 skin, 2 fat, 3 muscle "
                        "and other external soft tissue, 4 bone, 5 internal "
                        "soft tissue); empty: segment the CT.");
      prm.declare_entry("Work directory",
                        "",
                        Patterns::Anything(),
                        "Where the stages write their files (ct.nii.gz, "
                        "labels.nii.gz, skin and skull .ply/.vtp, "
                        "bone_parts.nii.gz, mesh.vtu/.msh). Empty: "
                        "'patient' in the output directory.");
      prm.declare_entry("Reuse earlier stages",
                        "true",
                        Patterns::Bool(),
                        "Skip a stage whose inputs and parameters are those of "
                        "its last run in the work directory.");
      prm.declare_entry("Post-operative skull",
                        "",
                        Patterns::Anything(),
                        "A post-operative skull surface (.ply or .vtp, the "
                        "patient frame) for 'softface plan', which registers "
                        "each bone part to it by ICP from the scene's "
                        "Planning and writes the recovered Planning; "
                        "'softface postop' writes one for a phantom, moved "
                        "by the scene's Planning. Empty: postop_skull.ply in "
                        "the work directory.");
      prm.declare_entry("Cut held by",
                        "",
                        Patterns::Anything(),
                        "The bone segment whose motion the faces where the "
                        "region of interest cuts the soft tissue follow "
                        "(usually the fixed cranium); empty: those faces are "
                        "free.");
      PhantomParameters::declare_parameters(prm);

      prm.enter_subsection("Segmentation");
      prm.declare_entry("Smoothing",
                        "0.5",
                        Patterns::Double(0.),
                        "Gaussian smoothing (mm) before the thresholds.");
      prm.declare_entry("Body threshold",
                        "-480",
                        Patterns::Double(),
                        "HU between air and skin.");
      prm.declare_entry("Bone threshold",
                        "520",
                        Patterns::Double(),
                        "HU between soft tissue and bone (the phantom's "
                        "midpoint; real scans often want 250-400).");
      prm.declare_entry("Fat threshold",
                        "-30",
                        Patterns::Double(),
                        "HU between fat and muscle.");
      prm.declare_entry("Skin thickness",
                        "2",
                        Patterns::Double(0.),
                        "Soft tissue within this depth (mm) of the body "
                        "surface is skin.");
      prm.declare_entry("Minimum bone volume",
                        "50",
                        Patterns::Double(0.),
                        "Bone pieces smaller than this (mm^3) are noise.");
      prm.leave_subsection();

      prm.enter_subsection("Region of interest");
      prm.declare_entry("Box",
                        "-1e9, -1e9, -1e9; 1e9, 1e9, 1e9",
                        Patterns::Anything(),
                        "The zone of the face that deforms (seed 3.1): 'xmin, "
                        "ymin, zmin; xmax, ymax, zmax' in the patient frame "
                        "(mm).");
      prm.declare_entry("Planes",
                        "",
                        Patterns::Anything(),
                        "Further cuts of the region: 'px, py, pz, nx, ny, nz; "
                        "...' (a point and the outward normal; the side the "
                        "normal points to is left out).");
      prm.leave_subsection();

      prm.enter_subsection("Mesh");
      prm.declare_entry("Target number of tetrahedra",
                        "100000",
                        Patterns::Integer(1000, 5000000),
                        "About how many tetrahedra (the cell size follows from "
                        "the soft tissue's volume), unless a cell size is "
                        "given.");
      prm.declare_entry("Cell size",
                        "0",
                        Patterns::Double(0.),
                        "Largest circumradius of a tetrahedron (mm); 0: from "
                        "the target number.");
      prm.declare_entry("Facet distance",
                        "1",
                        Patterns::Double(0.01),
                        "Largest distance (mm) between a boundary face and the "
                        "segmented surface.");
      prm.declare_entry("Facet angle",
                        "30",
                        Patterns::Double(1., 30.),
                        "Smallest angle of a boundary face (degrees).");
      prm.declare_entry("Radius-edge ratio",
                        "3",
                        Patterns::Double(2.),
                        "Largest circumradius / shortest edge of a "
                        "tetrahedron.");
      prm.declare_entry("Optimisation time",
                        "20",
                        Patterns::Double(0.),
                        "Seconds for each of CGAL's sliver perturbation and "
                        "exudation.");
      prm.declare_entry("Conforming tissue interfaces",
                        "false",
                        Patterns::Bool(),
                        "Mesh the interfaces between skin, fat and muscle as "
                        "well; false meshes the soft tissue as one domain and "
                        "gives each tetrahedron the tissue at its centroid "
                        "(better tetrahedra where a layer is thinner than a "
                        "cell, like the 2 mm skin).");
      prm.declare_entry("Sliver bound",
                        "12",
                        Patterns::Double(0., 30.),
                        "The smallest dihedral angle (degrees) CGAL's sliver "
                        "perturbation and exudation aim at.");
      prm.declare_entry("Seed",
                        "1",
                        Patterns::Integer(0),
                        "Seed of CGAL's random numbers.");
      prm.leave_subsection();

      OsteotomyParameters::declare_parameters(prm, cut_names);
      prm.leave_subsection();
    }

    std::vector<std::string>
    PatientParameters::cut_names(ParameterHandler &prm)
    {
      prm.enter_subsection("Patient");
      const auto names = OsteotomyParameters::cut_names(prm);
      prm.leave_subsection();
      return names;
    }

    void
    PatientParameters::parse_parameters(ParameterHandler  &prm,
                                        const std::string &input_directory,
                                        const std::string &default_work)
    {
      prm.enter_subsection("Patient");
      ct_volume      = resolve(prm.get("CT volume"), input_directory);
      label_volume   = resolve(prm.get("Label volume"), input_directory);
      work_directory = prm.get("Work directory");
      if (work_directory.empty())
        work_directory = default_work;
      reuse       = prm.get_bool("Reuse earlier stages");
      cut_held_by = prm.get("Cut held by");
      post_operative_skull =
        resolve(prm.get("Post-operative skull"), input_directory);
      if (post_operative_skull.empty())
        post_operative_skull =
          (fs::path(work_directory) / "postop_skull.ply").string();
      phantom.parse_parameters(prm);

      prm.enter_subsection("Segmentation");
      segmentation.smoothing       = prm.get_double("Smoothing");
      segmentation.body_threshold  = prm.get_double("Body threshold");
      segmentation.bone_threshold  = prm.get_double("Bone threshold");
      segmentation.fat_threshold   = prm.get_double("Fat threshold");
      segmentation.skin_thickness  = prm.get_double("Skin thickness");
      segmentation.min_bone_volume = prm.get_double("Minimum bone volume");
      prm.leave_subsection();

      prm.enter_subsection("Region of interest");
      const auto box =
        dealii::Utilities::split_string_list(prm.get("Box"), ';');
      if (box.size() != 2)
        throw Error("Scene/Patient/Region of interest/Box: expected 'xmin, "
                    "ymin, zmin; xmax, ymax, zmax' (got '" +
                    prm.get("Box") + "').");
      roi.box_min = parse_vec3(box[0], "Scene/Patient/Region of interest/Box");
      roi.box_max = parse_vec3(box[1], "Scene/Patient/Region of interest/Box");
      for (unsigned int d = 0; d < 3; ++d)
        if (!(roi.box_min[d] < roi.box_max[d]))
          throw Error("Scene/Patient/Region of interest/Box: its minimum "
                      "must lie below its maximum in every direction.");
      roi.planes.clear();
      for (const auto &plane :
           dealii::Utilities::split_string_list(prm.get("Planes"), ';'))
        {
          const std::string where = "Scene/Patient/Region of interest/Planes";
          const auto        v     = dealii::Utilities::split_string_list(plane);
          if (v.size() != 6)
            throw Error(where +
                        ": each plane is 'px, py, pz, nx, ny, nz' (got '" +
                        plane + "').");
          const Vec3 p = parse_vec3(v[0] + "," + v[1] + "," + v[2], where);
          const Vec3 n = parse_vec3(v[3] + "," + v[4] + "," + v[5], where);
          roi.planes.emplace_back(p, n);
        }
      prm.leave_subsection();

      prm.enter_subsection("Mesh");
      mesh.target_n_tetrahedra = prm.get_integer("Target number of tetrahedra");
      mesh.cell_size           = prm.get_double("Cell size");
      mesh.facet_distance      = prm.get_double("Facet distance");
      mesh.facet_angle         = prm.get_double("Facet angle");
      mesh.radius_edge_ratio   = prm.get_double("Radius-edge ratio");
      mesh.optimisation_seconds  = prm.get_double("Optimisation time");
      mesh.sliver_bound          = prm.get_double("Sliver bound");
      mesh.conforming_interfaces = prm.get_bool("Conforming tissue interfaces");
      mesh.seed                  = prm.get_integer("Seed");
      prm.leave_subsection();

      osteotomy.parse_parameters(prm);
      prm.leave_subsection();
    }

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
      const fs::path work(prm.work_directory);
      fs::create_directories(work);
      PatientModel model;
      const auto   figure = [&](const std::string &name,
                              const std::string &value) {
        model.figures.emplace_back(name, value);
      };
      // A stage's figures are kept beside its files, so that a reused
      // stage reports what it made.
      const auto save_figures = [&](const std::string &stage,
                                    const std::size_t  first) {
        std::ofstream out(work / (stage + ".figures"));
        for (std::size_t i = first; i < model.figures.size(); ++i)
          out << model.figures[i].first << '\t' << model.figures[i].second
              << '\n';
      };
      const auto load_figures = [&](const std::string &stage) {
        std::ifstream in(work / (stage + ".figures"));
        std::string   line;
        while (std::getline(in, line))
          {
            const auto tab = line.find('\t');
            if (tab != std::string::npos)
              model.figures.emplace_back(line.substr(0, tab),
                                         line.substr(tab + 1));
          }
      };
      const auto file = [&](const std::string &name) {
        return (work / name).string();
      };

      // 1. The CT: the phantom's acquisition, or the patient's file.
      StageClock  clock;
      CTVolume    ct;
      std::string ct_stamp;
      if (prm.ct_volume.empty())
        {
          const auto &p = prm.phantom;
          ct_stamp      = stamp_of("phantom",
                              Phantom::anatomy_version,
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
                  << clock.seconds() << " s)" << std::defaultfloat << std::endl;
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
              throw Error(std::string("Scene/Patient/CT volume: ") + e.what());
            }
          ct_stamp = stamp_of("file", file_stamp(prm.ct_volume));
          log << "    CT " << prm.ct_volume << ": " << ct.size[0] << " x "
              << ct.size[1] << " x " << ct.size[2] << " voxels" << std::endl;
        }
      figure("CT voxels",
             std::to_string(ct.size[0]) + " x " + std::to_string(ct.size[1]) +
               " x " + std::to_string(ct.size[2]));
      figure("voxel mm", number(ct.spacing[0]));
      if (last_stage == Stage::phantom)
        return model;

      // 2. Labels and the dense skin and skull surfaces.
      clock               = StageClock();
      const auto       &s = prm.segmentation;
      const std::string labels_stamp =
        ct_stamp + stamp_of("segmentation",
                            prm.label_volume.empty() ?
                              std::string("softface") :
                              file_stamp(prm.label_volume),
                            s.smoothing,
                            s.body_threshold,
                            s.bone_threshold,
                            s.fat_threshold,
                            s.skin_thickness,
                            s.min_bone_volume);
      LabelVolume labels;
      if (prm.reuse && up_to_date(work / "labels.stamp",
                                  labels_stamp,
                                  {file("labels.nii.gz"),
                                   file("skin.vtp"),
                                   file("skull.vtp")}))
        {
          labels = read_labels(file("labels.nii.gz"));
          load_figures("labels");
          log << "    segmentation: reused " << file("labels.nii.gz")
              << std::endl;
        }
      else
        {
          Volume<float> body_field, bone_field;
          double body_level = s.body_threshold, bone_level = s.bone_threshold;
          if (prm.label_volume.empty())
            {
              auto result =
                segment(ct,
                        s,
                        prm.ct_volume.empty() ? std::string("phantom") :
                                                prm.ct_volume);
              labels     = std::move(result.labels);
              body_field = std::move(result.smoothed);
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
                throw Error("Scene/Patient/Label volume '" + prm.label_volume +
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
          std::ofstream(work / "labels.stamp") << labels_stamp;
          const std::size_t first = model.figures.size();
          figure("skin vertices", std::to_string(skin.points.size()));
          figure("skull vertices", std::to_string(skull.points.size()));
          figure("segmentation s", number(clock.seconds()));
          save_figures("labels", first);
          log << "    segmentation: skin " << skin.points.size()
              << " vertices, skull " << skull.points.size() << " vertices ("
              << std::fixed << std::setprecision(1) << clock.seconds() << " s)"
              << std::defaultfloat << std::endl;
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
      if (last_stage == Stage::segmentation)
        return model;

      // 3. Bone parts and the tetrahedral mesh of the region of interest.
      clock = StageClock();
      std::ostringstream inputs;
      inputs << std::setprecision(17) << "mesh " << mesher_version << '\n';
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
             << m.radius_edge_ratio << ' ' << m.optimisation_seconds << ' '
             << m.sliver_bound << ' ' << m.conforming_interfaces << ' '
             << m.seed << '\n';
      const std::string mesh_stamp = labels_stamp + inputs.str();

      model.mesh_file = file("mesh.vtu");
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
              mesh =
                make_tetrahedral_mesh(labels,
                                      {skin_tissue, fat_tissue, muscle_tissue},
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
                          "segment.");
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
              << std::fixed << std::setprecision(1) << clock.seconds() << " s)"
              << std::defaultfloat << std::endl;
        }
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
  } // namespace Patient
} // namespace softface

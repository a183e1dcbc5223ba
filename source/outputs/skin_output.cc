// The predicted skins of a run (simulator; Mollemans et al. 2007,
// Sec. 3.4-3.5): the Skin parameters, step A of the chosen mappings once per
// scene, step B for every model, the skins as PLY/VTP and the distances to a
// post-operative skin.

#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/skin_output.h>
#include <softface/patient/backend.h>
#include <softface/patient/tetrahedral_mesh.h>
#include <softface/validation/tps_rpm.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <limits>

namespace softface
{
  namespace
  {
    SurfaceMapping::Surface
    read_skin(const std::string &filename, const std::string &parameter)
    {
      Patient::TriangleSurface surface;
      try
        {
          surface = Patient::backend().read_surface(filename);
        }
      catch (const Error &e)
        {
          throw Error(parameter + ": " + e.what());
        }
      SurfaceMapping::Surface s;
      for (const auto &p : surface.points)
        s.points.emplace_back(p[0], p[1], p[2]);
      s.triangles = surface.triangles;
      SurfaceMapping::check_manifold(s, parameter + " '" + filename + "'");
      return s;
    }

    Patient::TriangleSurface
    to_patient(const SurfaceMapping::Surface &s)
    {
      Patient::TriangleSurface surface;
      for (const auto &p : s.points)
        surface.points.push_back({{p[0], p[1], p[2]}});
      surface.triangles = s.triangles;
      return surface;
    }

    std::string
    short_name(const SurfaceMapping::Method method)
    {
      return method == SurfaceMapping::Method::shape_functions ? "sf" : "idw";
    }
  } // namespace

  bool
  SkinParameters::names_truth_scene(const std::string &file)
  {
    return file.size() > 4 && file.substr(file.size() - 4) == ".prm";
  }

  void
  SkinParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Skin");
    prm.declare_entry(
      "Skin surface",
      "auto",
      Patterns::Anything(),
      "The dense skin surface (.ply or .vtp, mm, in the mesh's frame) that "
      "every model's prediction is mapped onto (Mollemans et al. 2007, Sec. "
      "3.4). 'auto': the skin "
      "the patient pipeline made for a patient scene, none for other scenes; "
      "'none': no skin.");
    prm.declare_entry("Post-operative skin",
                      "",
                      Patterns::Anything(),
                      "The post-operative skin (.ply or .vtp, registered to "
                      "the pre-operative frame) that the predicted skins are "
                      "measured against (signed closest-point distances, "
                      "negative where the prediction lies behind it). A .prm "
                      "file instead: a scene whose run makes it (a phantom's "
                      "truth: one model, one mapping; its skin_<model>.ply), "
                      "run first unless its output folder holds the skin made "
                      "from the same file. Empty: no distances.");
    prm.declare_entry(
      "Mapping",
      "shape functions",
      Patterns::MultipleSelection("shape functions|inverse distance"),
      "How the mesh's displacement reaches the skin: 'shape functions' of "
      "the tetrahedron holding a skin point (or whose skin face it projects "
      "onto), 'inverse distance' weighting of the skin points matched to the "
      "mesh's skin vertices; both: every model mapped both ways.");
    prm.declare_entry("Mesh skin boundary ids",
                      "",
                      Patterns::List(Patterns::Integer(0, 255)),
                      "The boundary ids of the mesh's faces that are skin. "
                      "Empty: the patient pipeline's skin id for a patient "
                      "scene, every boundary face otherwise.");
    prm.declare_entry("Reach",
                      "3",
                      Patterns::Double(0.),
                      "Skin points farther than this (mm) from the mesh's "
                      "skin lie outside the simulated region and do not "
                      "move.");
    prm.declare_entry("Search radius",
                      "3",
                      Patterns::Double(0.),
                      "Inverse distance weighting: known points within this "
                      "distance (mm; x = 3 in Mollemans et al. 2007) ...");
    prm.declare_entry("Connectivity rings",
                      "5",
                      Patterns::Integer(1, 1000),
                      "... and fewer than this many edges away on the skin "
                      "(y = 5 in Mollemans et al. 2007).");
    prm.declare_entry("Correspondences",
                      "true",
                      Patterns::Bool(),
                      "With a post-operative skin: the distances between "
                      "corresponding points as well (Mollemans et al. 2007, "
                      "Sec. 3.5.1: a TPS-RPM "
                      "variant matches every measured point of a predicted "
                      "skin to the post-operative skin's surface). false: "
                      "closest-point distances only.");
    prm.declare_entry("Correspondence fit points",
                      "10000",
                      Patterns::Integer(1),
                      "The correspondences' thin-plate spline is fitted to "
                      "at most this many points of the measured region (a "
                      "fixed pseudo-random subset); every measured point is "
                      "then matched.");
    prm.declare_entry("Write distances",
                      "false",
                      Patterns::Bool(),
                      "Also write each predicted skin's signed distances to "
                      "the post-operative skin as skin_<model>_distance.csv "
                      "(one row per skin point, in the order of "
                      "skin_preoperative.ply; with exact correspondences "
                      "also the exact distance and its normal component; "
                      "with TPS-RPM correspondences also the correspondence "
                      "distance and the vector to the partner, nan where "
                      "there is none), for scripts.");
    prm.declare_entry("Masked boxes",
                      "",
                      Patterns::Anything(),
                      "Regions left out of the distance statistics (eyes, "
                      "neck): boxes 'x0, y0, z0; x1, y1, z1' (mm) separated "
                      "by '|'.");
    prm.leave_subsection();
  }

  void
  SkinParameters::parse_parameters(ParameterHandler  &prm,
                                   const std::string &input_directory,
                                   const std::string &patient_skin)
  {
    prm.enter_subsection("Skin");
    const auto relative = [&](std::string file) {
      if (!file.empty() && file[0] != '/' && !input_directory.empty())
        file = input_directory + "/" + file;
      return file;
    };
    skin_surface = prm.get("Skin surface");
    if (skin_surface == "auto")
      skin_surface = patient_skin;
    else if (skin_surface == "none")
      skin_surface.clear();
    else
      skin_surface = relative(skin_surface);
    post_operative_skin = relative(prm.get("Post-operative skin"));
    truth_scene.clear();
    if (names_truth_scene(post_operative_skin))
      std::swap(truth_scene, post_operative_skin);
    if ((!post_operative_skin.empty() || !truth_scene.empty()) &&
        skin_surface.empty())
      throw Error("Skin/Post-operative skin: given, but the scene has no "
                  "skin surface to predict (Skin/Skin surface).");
    methods.clear();
    for (const std::string &name :
         Utilities::split_string_list(prm.get("Mapping")))
      methods.push_back(SurfaceMapping::method_from_name(name));
    if (methods.empty())
      methods.push_back(SurfaceMapping::Method::shape_functions);
    mesh_skin_boundary_ids.clear();
    for (const int id : Utilities::string_to_int(
           Utilities::split_string_list(prm.get("Mesh skin boundary ids"))))
      mesh_skin_boundary_ids.insert(id);
    if (mesh_skin_boundary_ids.empty() && !patient_skin.empty())
      mesh_skin_boundary_ids.insert(Patient::skin_boundary_id);
    mapping.reach             = prm.get_double("Reach");
    mapping.radius            = prm.get_double("Search radius");
    mapping.rings             = prm.get_integer("Connectivity rings");
    write_distances           = prm.get_bool("Write distances");
    correspondences           = prm.get_bool("Correspondences");
    correspondence_fit_points = prm.get_integer("Correspondence fit points");
    mask =
      Validation::Mask::parse(prm.get("Masked boxes"), "Skin/Masked boxes");
    prm.leave_subsection();
  }

  SkinOutput::SkinOutput(const SkinParameters &parameters,
                         const Scene          &scene,
                         const std::string    &directory,
                         std::ostream         &out)
      : parameters(parameters)
      , directory(directory)
  {
    skin = read_skin(parameters.skin_surface, "Skin/Skin surface");
    if (!parameters.post_operative_skin.empty())
      post_operative =
        read_skin(parameters.post_operative_skin, "Skin/Post-operative skin");
    if (!parameters.truth_scene.empty())
      find_exact_correspondences(out);
    const auto mesh = SurfaceMapping::VolumeMesh::from_triangulation(
      scene.triangulation, parameters.mesh_skin_boundary_ids);
    if (mesh.skin.triangles.empty())
      throw Error("Skin/Mesh skin boundary ids: no boundary face of the mesh "
                  "has one of these ids.");
    out << "  skin " << parameters.skin_surface << ": " << skin.points.size()
        << " points, " << skin.triangles.size() << " triangles" << std::endl;
    for (const SurfaceMapping::Method method : parameters.methods)
      {
        SurfaceMapping::Parameters p = parameters.mapping;
        p.method                     = method;
        Timer timer;
        try
          {
            mappings.push_back(SurfaceMapping::initialise(mesh, skin, p));
          }
        catch (const Error &e)
          {
            throw Error("Skin/Skin surface '" + parameters.skin_surface +
                        "': " + e.what());
          }
        step_a_seconds.push_back(timer.wall_time());
        const auto &m = mappings.back();
        out << "  skin mapping (" << SurfaceMapping::name_of(method)
            << "): step A " << std::fixed << std::setprecision(3)
            << step_a_seconds.back() << " s; " << m.n_points() - m.n_outside
            << " points mapped, " << m.n_outside << " out of reach"
            << std::endl;
        if (m.n_without_neighbours > 0)
          out << "  skin mapping: warning: " << m.n_without_neighbours
              << " points within reach have no known point within " << p.radius
              << " mm and " << p.rings
              << " rings and do not move; widen Skin/Search radius or "
                 "Skin/Connectivity rings."
              << std::endl;
      }
    if (!post_operative.points.empty())
      {
        // Known before any model runs: a mask that leaves nothing to
        // measure where the mesh reaches.
        unsigned int n_measured = 0;
        for (unsigned int i = 0; i < skin.points.size(); ++i)
          n_measured +=
            !parameters.mask.masked(skin.points[i]) && mappings[0].in_reach[i];
        if (n_measured == 0)
          throw Error("Skin/Masked boxes: the mask leaves no point of the "
                      "skin to measure (all " +
                      std::to_string(skin.points.size()) +
                      " are in masked boxes or out of the mesh's reach).");
      }
    create_output_directory(directory);
    for (const std::string extension : {".ply", ".vtp"})
      {
        Patient::backend().write_surface(
          to_patient(skin), directory + "/skin_preoperative" + extension, {});
        if (!post_operative.points.empty())
          Patient::backend().write_surface(to_patient(post_operative),
                                           directory + "/skin_postoperative" +
                                             extension,
                                           {});
      }
  }

  void
  SkinOutput::find_exact_correspondences(std::ostream &out)
  {
    // The truth scene's run wrote the skin it moved beside its prediction.
    const std::string truth_skin =
      std::filesystem::path(parameters.post_operative_skin)
        .replace_filename("skin_preoperative.ply")
        .string();
    std::string why;
    if (!std::filesystem::exists(truth_skin))
      why = truth_skin + " does not exist";
    else
      {
        const auto moved = read_skin(truth_skin, "Skin/Post-operative skin");
        if (moved.points.size() != skin.points.size() ||
            post_operative.points.size() != skin.points.size())
          why = "the truth's skin has " + std::to_string(moved.points.size()) +
                " points, this one " + std::to_string(skin.points.size());
        else
          for (unsigned int i = 0; i < skin.points.size() && why.empty(); ++i)
            if (moved.points[i].distance(skin.points[i]) > 1e-4)
              why = "point " + std::to_string(i) + " of the truth's skin is " +
                    "not this skin's";
      }
    if (!why.empty())
      {
        out << "  exact correspondences: none (" << why << ")" << std::endl;
        return;
      }
    exact_normals = SurfaceMapping::point_normals(post_operative);
    out << "  exact correspondences: the truth moved the same "
        << skin.points.size() << " skin points" << std::endl;
  }

  void
  SkinOutput::map(const Scene               &scene,
                  const Vector<double>      &displacement,
                  std::vector<Tensor<1, 3>> &skin_displacement,
                  const unsigned int         mapping) const
  {
    // Step B: the vertex displacements gathered, then the weighted sums.
    std::vector<Tensor<1, 3>> vertex_u(scene.vertex_dofs().size());
    for (unsigned int v = 0; v < vertex_u.size(); ++v)
      if (scene.vertex_dofs()[v][0] != numbers::invalid_dof_index)
        for (unsigned int c = 0; c < 3; ++c)
          vertex_u[v][c] = displacement[scene.vertex_dofs()[v][c]];
    mappings[mapping].map(vertex_u, skin_displacement);
  }

  void
  SkinOutput::order_rows(const std::vector<std::string> &labels)
  {
    const auto position = [&labels](const Row &row) {
      return std::find(labels.begin(), labels.end(), row.model) -
             labels.begin();
    };
    std::stable_sort(rows.begin(), rows.end(), [&](const Row &a, const Row &b) {
      return position(a) < position(b);
    });
  }

  void
  SkinOutput::add_model(const std::string    &model,
                        const Scene          &scene,
                        const Vector<double> &displacement)
  {
    std::vector<Tensor<1, 3>> skin_u;
    for (unsigned int k = 0; k < mappings.size(); ++k)
      {
        Row row;
        row.model  = model;
        row.method = parameters.methods[k];
        Timer timer;
        map(scene, displacement, skin_u, k);
        row.step_b_seconds = timer.wall_time();

        SurfaceMapping::Surface predicted = skin;
        std::vector<double> u_values, distance_values, correspondence_values,
          correspondence_offsets;
        for (unsigned int i = 0; i < skin_u.size(); ++i)
          {
            predicted.points[i] += skin_u[i];
            row.max_displacement =
              std::max(row.max_displacement, skin_u[i].norm());
            for (unsigned int c = 0; c < 3; ++c)
              u_values.push_back(skin_u[i][c]);
          }
        std::vector<Patient::PointField> fields = {
          {"displacement", 3, u_values}};
        if (!post_operative.points.empty())
          {
            distance_values =
              Validation::signed_distances(predicted.points, post_operative);
            row.distances = Validation::statistics(distance_values,
                                                   skin.points,
                                                   parameters.mask,
                                                   mappings[k].in_reach);
            row.measured  = true;
            fields.push_back({"signed distance", 1, distance_values});
            if (parameters.correspondences)
              {
                correspond(predicted,
                           mappings[k].in_reach,
                           row,
                           correspondence_values,
                           correspondence_offsets);
                if (row.corresponded)
                  {
                    fields.push_back(
                      {"correspondence distance", 1, correspondence_values});
                    fields.push_back(
                      {"to correspondence", 3, correspondence_offsets});
                  }
              }
          }
        std::vector<double> exact_values, normal_values, exact_offsets;
        if (!exact_normals.empty())
          {
            for (unsigned int i = 0; i < skin.points.size(); ++i)
              {
                const Tensor<1, 3> e =
                  predicted.points[i] - post_operative.points[i];
                exact_values.push_back(e.norm());
                normal_values.push_back(e * exact_normals[i]);
                for (unsigned int d = 0; d < 3; ++d)
                  exact_offsets.push_back(-e[d]);
              }
            row.exact           = true;
            row.exact_distances = Validation::statistics(exact_values,
                                                         skin.points,
                                                         parameters.mask,
                                                         mappings[k].in_reach);
            row.exact_normal    = Validation::statistics(normal_values,
                                                      skin.points,
                                                      parameters.mask,
                                                      mappings[k].in_reach);
            fields.push_back({"exact distance", 1, exact_values});
            fields.push_back({"exact normal distance", 1, normal_values});
            fields.push_back({"to exact partner", 3, exact_offsets});
          }
        const std::string name =
          directory + "/skin_" + Outputs::file_name_of(model) +
          (parameters.methods.size() > 1 ? "_" + short_name(row.method) : "");
        Patient::backend().write_surface(to_patient(predicted),
                                         name + ".ply",
                                         {});
        Patient::backend().write_surface(to_patient(predicted),
                                         name + ".vtp",
                                         fields);
        if (parameters.write_distances && !distance_values.empty())
          {
            auto csv = open_output_file(name + "_distance.csv");
            csv << "signed distance mm"
                << (exact_values.empty() ? "" :
                                           ",exact distance mm,exact normal "
                                           "distance mm")
                << (row.corresponded ?
                      ",correspondence distance mm,to correspondence x mm,"
                      "to correspondence y mm,to correspondence z mm" :
                      "")
                << '\n'
                << std::setprecision(6);
            for (unsigned int i = 0; i < distance_values.size(); ++i)
              {
                csv << distance_values[i];
                if (!exact_values.empty())
                  csv << ',' << exact_values[i] << ',' << normal_values[i];
                if (row.corresponded)
                  {
                    csv << ',' << correspondence_values[i];
                    for (unsigned int d = 0; d < 3; ++d)
                      csv << ',' << correspondence_offsets[3 * i + d];
                  }
                csv << '\n';
              }
          }
        rows.push_back(row);
      }
  }

  void
  SkinOutput::correspond(const SurfaceMapping::Surface &predicted,
                         const std::vector<bool>       &in_reach,
                         Row                           &row,
                         std::vector<double>           &distance,
                         std::vector<double>           &offset) const
  {
    Timer        timer;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    distance.assign(predicted.points.size(), nan);
    offset.assign(3 * predicted.points.size(), nan);
    // The measured region of the prediction, matched to the whole
    // post-operative surface.
    std::vector<unsigned int> measured;
    for (unsigned int i = 0; i < predicted.points.size(); ++i)
      if (in_reach[i] && !parameters.mask.masked(skin.points[i]))
        measured.push_back(i);
    if (measured.empty())
      return;
    Eigen::MatrixX3d source(measured.size(), 3);
    for (unsigned int k = 0; k < measured.size(); ++k)
      for (unsigned int d = 0; d < 3; ++d)
        source(k, d) = predicted.points[measured[k]][d];
    Validation::TpsRpmParameters tps_rpm;
    tps_rpm.fit_points = parameters.correspondence_fit_points;
    const auto result  = Validation::tps_rpm(source, post_operative, tps_rpm);
    // Points without a counterpart on the post-operative skin (their match
    // lies on its rim: the scan ends there) are left out of the statistics.
    std::vector<double> distances;
    for (Eigen::Index k = 0; k < result.distance.size(); ++k)
      if (!result.beyond_rim[k])
        {
          const unsigned int i = measured[k];
          distances.push_back(result.distance[k]);
          distance[i] = result.distance[k];
          for (unsigned int d = 0; d < 3; ++d)
            offset[3 * i + d] =
              result.correspondence(k, d) - predicted.points[i][d];
        }
    if (distances.empty())
      return;
    std::vector<Point<3>> where(distances.size());
    row.correspondence         = Validation::statistics(distances, where, {});
    row.corresponded           = true;
    row.correspondence_points  = distances.size();
    row.correspondence_seconds = timer.wall_time();
  }

  void
  SkinOutput::write(std::ostream &out) const
  {
    auto csv = open_output_file(directory + "/skin.csv");
    csv << "model,mapping,skin points,mapped points,unmoved points,step A s,"
           "step B s,"
           "max |u| mm,measured points,mean mm,mean |d| mm,variance mm2,"
           "max |d| mm,p50 mm,p90 mm,p95 mm,correspondence points,"
           "correspondence s,correspondence mean mm,correspondence p50 mm,"
           "correspondence p90 mm,correspondence p95 mm,"
           "correspondence max mm,exact mean mm,exact p50 mm,exact p90 mm,"
           "exact p95 mm,exact max mm,exact normal mean mm,"
           "exact normal variance mm2,weights per point,step A parts\n";
    csv << std::setprecision(10);
    out << "\nSkin (" << skin.points.size() << " points"
        << (post_operative.points.empty() ? "" :
                                            "; distances to the post-operative "
                                            "skin, mm")
        << ")\n";
    // Wide enough for "model, plan" when a scene runs several plans.
    std::size_t model_width = 16;
    for (const Row &row : rows)
      model_width = std::max(model_width, row.model.size() + 2);
    out << std::left << std::setw(model_width) << "model" << std::setw(18)
        << "mapping" << std::right << std::setw(10) << "step A s"
        << std::setw(10) << "step B s" << std::setw(10) << "max |u|";
    if (!post_operative.points.empty())
      out << std::setw(9) << "mean" << std::setw(9) << "p50" << std::setw(9)
          << "p90" << std::setw(9) << "p95" << std::setw(9) << "max";
    if (!post_operative.points.empty() && parameters.correspondences)
      out << std::setw(14) << "corr. p50" << std::setw(10) << "corr. p90";
    if (!exact_normals.empty())
      out << std::setw(14) << "exact p50" << std::setw(11) << "exact p90";
    out << '\n';
    for (const Row &row : rows)
      {
        unsigned int k = 0;
        while (parameters.methods[k] != row.method)
          ++k;
        const auto &m = mappings[k];
        csv << csv_field(row.model) << ','
            << SurfaceMapping::name_of(row.method) << ',' << m.n_points() << ','
            << m.n_points() - m.n_outside << ',' << m.n_without_neighbours
            << ',' << step_a_seconds[k] << ',' << row.step_b_seconds << ','
            << row.max_displacement;
        if (row.measured)
          csv << ',' << row.distances.n << ',' << row.distances.mean << ','
              << row.distances.mean_absolute << ',' << row.distances.variance
              << ',' << row.distances.max_absolute << ',' << row.distances.p50
              << ',' << row.distances.p90 << ',' << row.distances.p95;
        else
          csv << ",,,,,,,,";
        if (row.corresponded)
          csv << ',' << row.correspondence_points << ','
              << row.correspondence_seconds << ',' << row.correspondence.mean
              << ',' << row.correspondence.p50 << ',' << row.correspondence.p90
              << ',' << row.correspondence.p95 << ','
              << row.correspondence.max_absolute;
        else
          csv << ",,,,,,,";
        if (row.exact)
          csv << ',' << row.exact_distances.mean << ','
              << row.exact_distances.p50 << ',' << row.exact_distances.p90
              << ',' << row.exact_distances.p95 << ','
              << row.exact_distances.max_absolute << ','
              << row.exact_normal.mean << ',' << row.exact_normal.variance;
        else
          csv << ",,,,,,,";
        // What step B costs per point, and where step A's time goes.
        csv << ','
            << static_cast<double>(m.vertices.size()) /
                 std::max(1u, m.n_points() - m.n_outside)
            << ',';
        for (unsigned int j = 0; j < m.step_a_parts.size(); ++j)
          csv << (j > 0 ? ";" : "") << m.step_a_parts[j].first << '='
              << m.step_a_parts[j].second;
        csv << '\n';
        out << std::left << std::setw(model_width) << row.model << std::setw(18)
            << SurfaceMapping::name_of(row.method) << std::right << std::fixed
            << std::setprecision(3) << std::setw(10) << step_a_seconds[k]
            << std::setw(10) << row.step_b_seconds << std::setw(10)
            << std::setprecision(2) << row.max_displacement;
        if (row.measured)
          out << std::setw(9) << row.distances.mean << std::setw(9)
              << row.distances.p50 << std::setw(9) << row.distances.p90
              << std::setw(9) << row.distances.p95 << std::setw(9)
              << row.distances.max_absolute;
        if (row.corresponded)
          out << std::setw(14) << row.correspondence.p50 << std::setw(10)
              << row.correspondence.p90;
        if (row.exact)
          out << std::setw(14) << row.exact_distances.p50 << std::setw(11)
              << row.exact_distances.p90;
        out << '\n';
      }
  }
} // namespace softface

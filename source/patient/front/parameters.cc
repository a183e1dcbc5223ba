// The parameters of subsection Scene/Patient and its subsections: declared
// and parsed in the core, which needs them for every scene (the handler
// declares every subsection), while the pipeline that uses them is loaded
// only when a scene asks for it (backend.h).

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/vec3_parameter.h>
#include <softface/patient/pipeline.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    using namespace dealii;

    namespace
    {
      namespace fs = std::filesystem;

      // A relative file is taken from the parameter file's folder.
      std::string
      resolve(const std::string &file, const std::string &directory)
      {
        if (file.empty() || fs::path(file).is_absolute() || directory.empty())
          return file;
        return (fs::path(directory) / file).string();
      }

      // A direction given by the user, of length 1.
      Vec3
      normalised(Vec3 v, const std::string &where)
      {
        const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(n > 0.))
          throw Error(where + ": a zero vector.");
        for (auto &x : v)
          x /= n;
        return v;
      }

      // A default value as the documentation shows it.
      std::string
      number(const double x)
      {
        std::ostringstream s;
        s << std::setprecision(4) << x;
        return s.str();
      }

      // The Scene/Patient/Segmentation subsection.
      void
      declare_segmentation_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Segmentation");
        prm.declare_entry("Smoothing",
                          "0.5",
                          Patterns::Double(0.),
                          "Gaussian smoothing (mm) before the thresholds.");
        // A number, or 'auto' (checked when parsed, with the parameter's
        // name in the message).
        const auto        threshold = Patterns::Anything();
        const std::string automatic =
          " 'auto': chosen from the scan's histogram (Otsu's threshold "
          "splits the voxels concerned into two classes; the threshold is "
          "the midpoint of their peaks, for bone 45 % of the way from soft "
          "tissue's to bone's), for a CT in other units than HU; "
          "the value chosen is printed and written to thresholds.txt in "
          "the work directory.";
        prm.declare_entry("Body threshold",
                          "-480",
                          threshold,
                          "HU between air and skin, or 'auto' (air against "
                          "every other voxel)." +
                            automatic);
        prm.declare_entry("Bone threshold",
                          "520",
                          threshold,
                          "HU between soft tissue and bone (the phantom's "
                          "midpoint; real scans often want 250-400), or "
                          "'auto' (soft tissue against bone, within the "
                          "body)." +
                            automatic);
        prm.declare_entry("Fat threshold",
                          "-30",
                          threshold,
                          "HU between fat and muscle, or 'auto' (fat against "
                          "muscle, within the facial soft tissue under the "
                          "skin)." +
                            automatic);
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
      }

      // The Scene/Patient/Region of interest subsection.
      void
      declare_region_of_interest(ParameterHandler &prm)
      {
        prm.enter_subsection("Region of interest");
        prm.declare_entry("Box",
                          "-1e9, -1e9, -1e9; 1e9, 1e9, 1e9",
                          Patterns::Anything(),
                          "The zone of the face that deforms (Mollemans et al. "
                          "2007, Sec. 3.1): 'xmin, "
                          "ymin, zmin; xmax, ymax, zmax' in the patient frame "
                          "(mm).");
        prm.declare_entry(
          "Planes",
          "",
          Patterns::Anything(),
          "Further cuts of the region: 'px, py, pz, nx, ny, nz; "
          "...' (a point and the outward normal; the side the "
          "normal points to is left out).");
        prm.leave_subsection();
      }

      // The Scene/Patient/Preview subsection ('softface preview').
      void
      declare_preview(ParameterHandler &prm)
      {
        prm.enter_subsection("Preview");
        prm.declare_entry(
          "Point",
          "",
          Patterns::Anything(),
          "The point 'x, y, z' (mm, patient frame) that the axial, coronal "
          "and sagittal slices of 'softface preview' pass through. Empty: "
          "the centre of the region of interest's box where it lies in the "
          "CT, else the centre of the CT.");
        prm.leave_subsection();
      }

      // The Scene/Patient/Mesh subsection.
      void
      declare_mesh_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Mesh");
        prm.declare_entry(
          "Target number of tetrahedra",
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
        prm.declare_entry(
          "Facet distance",
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
        prm.declare_entry(
          "Optimisation safety limit",
          "600",
          Patterns::Double(0.),
          "Wall-clock seconds after which CGAL's sliver perturbation or "
          "exudation ends the run with an error (0: no limit). Each runs until "
          "every dihedral angle reaches the sliver bound or no move improves "
          "the worst one, so the mesh is the same on an idle or a busy "
          "machine; "
          "the limit only stops a run that would take too long.");
        prm.declare_entry(
          "Conforming tissue interfaces",
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
                        "DICOM series, in Hounsfield units (in other units, "
                        "set the segmentation's thresholds to 'auto'). Empty: "
                        "the phantom of subsection Phantom. Relative to the "
                        "parameter file's folder.");
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
                        "its last run in the work directory, made by the same "
                        "build of softface with the same ITK, VTK and CGAL.");
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
      declare_segmentation_parameters(prm);
      declare_region_of_interest(prm);
      declare_preview(prm);
      declare_mesh_parameters(prm);
      OsteotomyParameters::declare_parameters(prm, cut_names);
      RegistrationStageParameters::declare_parameters(prm);
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
      segmentation.smoothing = prm.get_double("Smoothing");
      // A threshold's number, or 'auto': the default number is kept and
      // the segmentation chooses one from the scan.
      const auto threshold =
        [&](const std::string &name, double &value, bool &automatic) {
          const std::string text = Utilities::trim(prm.get(name));
          automatic              = text == "auto";
          if (automatic)
            return;
          std::istringstream in(text);
          double             x = 0.;
          if (!(in >> x) || !(in >> std::ws).eof() || !std::isfinite(x))
            throw Error("Scene/Patient/Segmentation/" + name +
                        ": expected a number (HU) or 'auto' (got '" + text +
                        "').");
          value = x;
        };
      threshold("Body threshold",
                segmentation.body_threshold,
                segmentation.auto_body_threshold);
      threshold("Bone threshold",
                segmentation.bone_threshold,
                segmentation.auto_bone_threshold);
      threshold("Fat threshold",
                segmentation.fat_threshold,
                segmentation.auto_fat_threshold);
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
      mesh.optimisation_safety_seconds =
        prm.get_double("Optimisation safety limit");
      mesh.sliver_bound          = prm.get_double("Sliver bound");
      mesh.conforming_interfaces = prm.get_bool("Conforming tissue interfaces");
      mesh.seed                  = prm.get_integer("Seed");
      prm.leave_subsection();

      prm.enter_subsection("Preview");
      const std::string point = prm.get("Point");
      preview_point_given     = !Utilities::trim(point).empty();
      if (preview_point_given)
        preview_point = parse_vec3(point, "Scene/Patient/Preview/Point");
      prm.leave_subsection();

      osteotomy.parse_parameters(prm);
      registration.parse_parameters(prm, input_directory);
      prm.leave_subsection();
    }

    void
    RegistrationStageParameters::declare_parameters(ParameterHandler &prm)
    {
      const RegistrationParameters defaults;
      const auto                   join = [](const auto &values) {
        std::ostringstream s;
        for (std::size_t i = 0; i < values.size(); ++i)
          s << (i > 0 ? ", " : "") << values[i];
        return s.str();
      };
      prm.enter_subsection("Registration");
      prm.declare_entry("Post-operative CT",
                        "",
                        Patterns::Anything(),
                        "The post-operative CT that 'softface register' "
                        "registers rigidly to the pre-operative one ('CT "
                        "volume', or the phantom's): a volume file or a "
                        "folder with a DICOM series, as 'CT volume'. Relative "
                        "to the parameter file's folder. Empty: none.");
      prm.declare_entry("Post-operative surfaces",
                        "",
                        Patterns::Anything(),
                        "Surfaces made from the post-operative CT (.ply or "
                        ".vtp, comma-separated, in its frame), each written "
                        "carried into the pre-operative frame as "
                        "<name>_registered.ply in the output directory: the "
                        "registered post-operative skin is what "
                        "'Skin/Post-operative skin' takes.");
      prm.declare_entry("Subvolume",
                        "",
                        Patterns::Anything(),
                        "The part of the head the surgery leaves unaltered "
                        "(typically the top of the skull, above the orbits), "
                        "'x0, y0, z0; x1, y1, z1' in the pre-operative CT's "
                        "frame (mm): the metric sees only the voxels whose "
                        "centres lie in it (the box may reach past the CT). "
                        "Empty: the whole pre-operative CT.");
      prm.declare_entry("Restriction",
                        "crop",
                        Patterns::Selection("crop|mask"),
                        "How the metric is kept to the subvolume: 'crop' "
                        "the pre-operative CT to it, or 'mask' the whole CT "
                        "(about 1.5 times slower; on the phantom both "
                        "recover the motion to 0.1 mm).");
      prm.declare_entry("Initializer",
                        "identity",
                        Patterns::Selection("identity|geometry|moments"),
                        "Where the search starts: 'identity' (no motion: "
                        "the two scans' frames roughly agree), 'geometry' "
                        "(the centres of the two fields of view matched) or "
                        "'moments' (the centres of mass, HU + 1000, "
                        "matched). No rotation in any case.");
      prm.declare_entry("Histogram bins",
                        std::to_string(defaults.histogram_bins),
                        Patterns::Integer(5, 1000),
                        "Bins of Mattes mutual information's joint "
                        "histogram (at most 1000: the histogram holds the "
                        "square of this many bins).");
      prm.declare_entry("Samples",
                        std::to_string(defaults.samples),
                        Patterns::Integer(0),
                        "At most this many sample points per level (every "
                        "k-th voxel of the subvolume, jittered by a third of "
                        "a voxel); 0: every voxel.");
      prm.declare_entry("Seed",
                        std::to_string(defaults.seed),
                        Patterns::Integer(0),
                        "Seed of the samples' jitter: the same seed, the "
                        "same result.");
      prm.declare_entry("Shrink factors",
                        join(defaults.shrink_factors),
                        Patterns::List(Patterns::Integer(1)),
                        "The multi-resolution schedule, coarse to fine: each "
                        "level's voxels are this many of the CTs' (the "
                        "subvolume must hold 4 coarsest voxels across).");
      prm.declare_entry("Smoothing sigmas",
                        join(defaults.smoothing_sigmas),
                        Patterns::List(Patterns::Double(0.)),
                        "Gaussian smoothing (mm) of each level, one per "
                        "shrink factor.");
      prm.declare_entry("Optimizer",
                        "regular step",
                        Patterns::Selection("regular step|conjugate gradient"),
                        "'regular step' gradient descent, or 'conjugate "
                        "gradient' (Polak-Ribiere) with a golden-section line "
                        "search (3 times slower on the phantom, no more "
                        "accurate); both on parameters scaled by the "
                        "physical shift each causes.");
      prm.declare_entry("Learning rate",
                        number(defaults.learning_rate),
                        Patterns::Double(0.),
                        "The first step (about mm) of the first level; a "
                        "later level's is this times its shrink factor over "
                        "the first level's. Conjugate gradient: the largest "
                        "motion (mm) of a voxel in its first step.");
      prm.declare_entry("Minimum step",
                        number(defaults.minimum_step),
                        Patterns::Double(0.),
                        "Regular step: a level ends when its step, relaxed "
                        "at every change of direction, falls below this "
                        "(about mm).");
      prm.declare_entry("Relaxation",
                        number(defaults.relaxation),
                        Patterns::Double(0., 1.),
                        "Regular step: the step times this at every change "
                        "of direction.");
      prm.declare_entry("Convergence",
                        number(defaults.convergence),
                        Patterns::Double(0.),
                        "Conjugate gradient: a level ends when the metric's "
                        "trend over the convergence window falls below "
                        "this.");
      prm.declare_entry("Convergence window",
                        std::to_string(defaults.convergence_window),
                        Patterns::Integer(1),
                        "Conjugate gradient: iterations of that trend.");
      prm.declare_entry("Maximum iterations",
                        std::to_string(defaults.max_iterations),
                        Patterns::Integer(1),
                        "At most this many iterations per level.");
      prm.declare_entry("Threads",
                        std::to_string(defaults.threads),
                        Patterns::Integer(1),
                        "Threads of the metric. With one the result is the "
                        "same to the last digit from run to run; with more, "
                        "ITK sums the metric's derivative in the order the "
                        "threads finish and the last digits vary.");
      prm.leave_subsection();
    }

    void
    RegistrationStageParameters::parse_parameters(
      ParameterHandler  &prm,
      const std::string &input_directory)
    {
      const std::string where = "Scene/Patient/Registration/";
      prm.enter_subsection("Registration");
      post_operative_ct =
        resolve(prm.get("Post-operative CT"), input_directory);
      post_operative_surfaces.clear();
      for (const auto &file : dealii::Utilities::split_string_list(
             prm.get("Post-operative surfaces")))
        post_operative_surfaces.push_back(resolve(file, input_directory));

      using R = RegistrationParameters;
      auto &r = registration;
      r.subvolume.reset();
      if (!prm.get("Subvolume").empty())
        r.subvolume = parse_box(prm.get("Subvolume"), where + "Subvolume");
      r.restriction = prm.get("Restriction") == "mask" ? R::Restriction::mask :
                                                         R::Restriction::crop;
      r.initializer = R::Initializer::identity;
      if (prm.get("Initializer") == "geometry")
        r.initializer = R::Initializer::geometry;
      else if (prm.get("Initializer") == "moments")
        r.initializer = R::Initializer::moments;

      r.histogram_bins = prm.get_integer("Histogram bins");
      r.samples        = prm.get_integer("Samples");
      r.seed           = prm.get_integer("Seed");
      r.shrink_factors.clear();
      for (const auto &f :
           dealii::Utilities::split_string_list(prm.get("Shrink factors")))
        r.shrink_factors.push_back(dealii::Utilities::string_to_int(f));
      r.smoothing_sigmas.clear();
      for (const auto &s :
           dealii::Utilities::split_string_list(prm.get("Smoothing sigmas")))
        r.smoothing_sigmas.push_back(dealii::Utilities::string_to_double(s));
      if (r.shrink_factors.empty() ||
          r.shrink_factors.size() != r.smoothing_sigmas.size())
        throw Error(where + "Smoothing sigmas: one per shrink factor (" +
                    std::to_string(r.shrink_factors.size()) +
                    " shrink factors, " +
                    std::to_string(r.smoothing_sigmas.size()) + " sigmas).");

      r.optimizer          = prm.get("Optimizer") == "conjugate gradient" ?
                               R::Optimizer::conjugate_gradient :
                               R::Optimizer::regular_step;
      r.learning_rate      = prm.get_double("Learning rate");
      r.minimum_step       = prm.get_double("Minimum step");
      r.relaxation         = prm.get_double("Relaxation");
      r.convergence        = prm.get_double("Convergence");
      r.convergence_window = prm.get_integer("Convergence window");
      r.max_iterations     = prm.get_integer("Maximum iterations");
      r.threads            = prm.get_integer("Threads");
      prm.leave_subsection();
    }

    void
    PhantomParameters::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Phantom");
      prm.declare_entry("Voxel size",
                        "1",
                        Patterns::Double(0.1, 5.),
                        "Isotropic voxel size of the CT volume in mm (0.5 for "
                        "a fine scan).");
      prm.declare_entry("Field of view",
                        "180, 240, 256",
                        Patterns::List(Patterns::Double(10.), 3, 3),
                        "Extent of the volume in x, y, z (mm).");
      prm.declare_entry("Field of view centre",
                        "0, -5, 0",
                        Patterns::List(Patterns::Double(), 3, 3),
                        "Centre of the volume in the patient frame (mm; LPS: "
                        "x to the patient's left, y posterior, z superior).");
      prm.declare_entry("Face width",
                        "1",
                        Patterns::Double(0.7, 1.4),
                        "Scale of the face across (x).");
      prm.declare_entry("Face height",
                        "1",
                        Patterns::Double(0.7, 1.4),
                        "Scale of the lower face in height (z).");
      prm.declare_entry("Soft tissue thickness",
                        "0",
                        Patterns::Double(-4., 10.),
                        "Soft tissue added over the face (mm; negative for a "
                        "lean face).");
      prm.declare_entry("Mandible length",
                        "1",
                        Patterns::Double(0.8, 1.25),
                        "Scale of the mandibular body from the gonion to the "
                        "symphysis.");
      prm.declare_entry("Mandible angle",
                        "120",
                        Patterns::Double(100., 140.),
                        "Gonial angle in degrees: larger turns the body and "
                        "the chin downwards.");
      prm.declare_entry("Profile",
                        "class I",
                        Patterns::Selection("class I|class II|class III"),
                        "Skeletal class: 'class II' sets the mandible back by "
                        "the jaw discrepancy (retrognathic), 'class III' "
                        "forward (prognathic).");
      prm.declare_entry("Jaw discrepancy",
                        "6",
                        Patterns::Double(0., 15.),
                        "How far (mm) a class II or III mandible sits behind "
                        "or in front of a class I one.");
      prm.declare_entry("Mouth",
                        "open",
                        Patterns::Selection("open|closed"),
                        "'open': the teeth and the lips part by 3 mm; "
                        "'closed': the teeth in occlusion and the lips "
                        "together, as most patients are scanned. Upper and "
                        "lower teeth then touch on the occlusal plane (z = "
                        "-20), so a scene separates the jaws by a cut there.");
      prm.declare_entry("Noise",
                        "15",
                        Patterns::Double(0.),
                        "Standard deviation of the image noise (HU).");
      prm.declare_entry("Blur",
                        "0.5",
                        Patterns::Double(0.),
                        "Standard deviation of the scanner's point spread "
                        "(mm).");
      prm.declare_entry("Metal streaks",
                        "false",
                        Patterns::Bool(),
                        "Metal fillings in the four first molars, with the "
                        "bright and dark streaks they cast in their axial "
                        "slices.");
      prm.declare_entry("Seed",
                        "1",
                        Patterns::Integer(0),
                        "Seed of the noise (the same seed gives the same "
                        "volume).");
      prm.leave_subsection();
    }

    void
    PhantomParameters::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Phantom");
      voxel_size            = prm.get_double("Voxel size");
      field_of_view         = parse_vec3(prm.get("Field of view"),
                                 "Scene/Patient/Phantom/Field of view");
      centre                = parse_vec3(prm.get("Field of view centre"),
                          "Scene/Patient/Phantom/Field of view centre");
      face_width            = prm.get_double("Face width");
      face_height           = prm.get_double("Face height");
      soft_tissue_thickness = prm.get_double("Soft tissue thickness");
      mandible_length       = prm.get_double("Mandible length");
      mandible_angle        = prm.get_double("Mandible angle");
      profile               = prm.get("Profile");
      jaw_discrepancy       = prm.get_double("Jaw discrepancy");
      closed_mouth          = prm.get("Mouth") == "closed";
      noise                 = prm.get_double("Noise");
      blur                  = prm.get_double("Blur");
      metal_streaks         = prm.get_bool("Metal streaks");
      seed                  = prm.get_integer("Seed");
      prm.leave_subsection();
    }

    void
    OsteotomyParameters::declare_parameters(
      ParameterHandler               &prm,
      const std::vector<std::string> &names)
    {
      prm.enter_subsection("Osteotomy");
      prm.declare_entry("Cuts",
                        "",
                        Patterns::List(Patterns::Anything()),
                        "Names of the cut surfaces (e.g. le fort I, bsso left, "
                        "bsso right, genioplasty), each described in a "
                        "subsection 'Cut <name>'. No cut: the skull is one "
                        "part.");
      prm.declare_entry("Kerf",
                        "1.5",
                        Patterns::Double(0.1, 10.),
                        "Width of a saw cut (mm): bone within half of it from "
                        "a cut surface separates the parts (at least one "
                        "voxel, so that a cut always separates).");
      prm.declare_entry("Detached margin",
                        "3",
                        Patterns::Double(0., 50.),
                        "Soft tissue touching bone within this distance (mm) "
                        "of a cut is attached to neither part (it is free): "
                        "the periosteum is lifted along an osteotomy, and "
                        "tissue pinned to two parts that move apart would be "
                        "torn. A nonzero margin reaches at least one voxel "
                        "beyond the kerf, so that coarse voxels detach the "
                        "tissue in the kerf too. 0: every contact is a join "
                        "point.");
      prm.declare_entry("Minimum part volume",
                        "500",
                        Patterns::Double(0.),
                        "Bone pieces smaller than this (mm^3) are slivers of "
                        "a cut or noise; they join the nearest part.");
      for (const std::string &name : names)
        {
          prm.enter_subsection("Cut " + name);
          prm.declare_entry("Type",
                            "plane",
                            Patterns::Selection("plane|swept polyline"),
                            "'plane' (Point and Normal) or 'swept polyline' "
                            "(Polyline swept along Sweep direction).");
          prm.declare_entry("Point",
                            "0, 0, 0",
                            Patterns::Anything(),
                            "A point of the plane (mm, 'x, y, z').");
          prm.declare_entry("Normal",
                            "0, 0, 1",
                            Patterns::Anything(),
                            "The plane's normal ('x, y, z').");
          prm.declare_entry("Polyline",
                            "",
                            Patterns::Anything(),
                            "Points of the polyline 'x, y, z; x, y, z; ...' "
                            "(mm).");
          prm.declare_entry("Sweep direction",
                            "1, 0, 0",
                            Patterns::Anything(),
                            "Direction the polyline is swept along.");
          prm.declare_entry("Box",
                            "",
                            Patterns::Anything(),
                            "The cut acts only inside this box 'xmin, ymin, "
                            "zmin; xmax, ymax, zmax' (mm); empty: everywhere.");
          prm.declare_entry("Detached margin",
                            "",
                            Patterns::Anything(),
                            "This cut's detached margin (mm), where the "
                            "surgery lifts more or less tissue than along "
                            "the other cuts: a setback by sagittal split "
                            "strips the ramus and trims the overlapping "
                            "bone. Empty: the osteotomy's 'Detached "
                            "margin'.");
          prm.leave_subsection();
        }
      prm.leave_subsection();
    }

    std::vector<std::string>
    OsteotomyParameters::cut_names(ParameterHandler &prm)
    {
      prm.enter_subsection("Osteotomy");
      const auto names = dealii::Utilities::split_string_list(prm.get("Cuts"));
      prm.leave_subsection();
      return names;
    }

    void
    OsteotomyParameters::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Osteotomy");
      kerf            = prm.get_double("Kerf");
      detached_margin = prm.get_double("Detached margin");
      min_part_volume = prm.get_double("Minimum part volume");
      cuts.clear();
      for (const std::string &name :
           dealii::Utilities::split_string_list(prm.get("Cuts")))
        {
          const std::string where = "Scene/Patient/Osteotomy/Cut " + name;
          prm.enter_subsection("Cut " + name);
          Cut cut;
          cut.name = name;
          cut.type = prm.get("Type");
          if (cut.type == "plane")
            {
              cut.point = parse_vec3(prm.get("Point"), where + "/Point");
              cut.normal =
                normalised(parse_vec3(prm.get("Normal"), where + "/Normal"),
                           where + "/Normal");
            }
          else
            {
              for (const std::string &p :
                   dealii::Utilities::split_string_list(prm.get("Polyline"),
                                                        ';'))
                cut.polyline.push_back(parse_vec3(p, where + "/Polyline"));
              if (cut.polyline.size() < 2)
                throw Error(where +
                            "/Polyline: a swept polyline needs at least "
                            "two points.");
              cut.sweep = normalised(parse_vec3(prm.get("Sweep direction"),
                                                where + "/Sweep direction"),
                                     where + "/Sweep direction");
            }
          const auto box =
            dealii::Utilities::split_string_list(prm.get("Box"), ';');
          if (box.size() == 2)
            {
              cut.box_min = parse_vec3(box[0], where + "/Box");
              cut.box_max = parse_vec3(box[1], where + "/Box");
            }
          else if (!box.empty())
            throw Error(where + "/Box: expected 'xmin, ymin, zmin; xmax, ymax, "
                                "zmax'.");
          cut.detached_margin      = detached_margin;
          const std::string margin = prm.get("Detached margin");
          if (!margin.empty())
            {
              if (!Patterns::Double(0., 50.).match(margin))
                throw Error(where +
                            "/Detached margin: expected a distance "
                            "from 0 to 50 mm or nothing (got '" +
                            margin + "').");
              cut.detached_margin = dealii::Utilities::string_to_double(margin);
            }
          prm.leave_subsection();
          cuts.push_back(cut);
        }
      prm.leave_subsection();
    }


    Box
    parse_box(const std::string &text, const std::string &where)
    {
      const auto semicolon = text.find(';');
      if (semicolon == std::string::npos ||
          text.find(';', semicolon + 1) != std::string::npos)
        throw Error(where +
                    ": expected two corners 'x0, y0, z0; x1, y1, z1' (got '" +
                    text + "').");
      const Vec3 a = parse_vec3(text.substr(0, semicolon), where);
      const Vec3 b = parse_vec3(text.substr(semicolon + 1), where);
      Box        box;
      for (unsigned int d = 0; d < 3; ++d)
        {
          box.lower[d] = std::min(a[d], b[d]);
          box.upper[d] = std::max(a[d], b[d]);
          if (!(box.upper[d] > box.lower[d]))
            throw Error(where + ": the box '" + text + "' is empty (its " +
                        std::string(1, char('x' + d)) + " extent is 0 mm).");
        }
      return box;
    }
  } // namespace Patient
} // namespace softface

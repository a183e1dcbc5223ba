#ifndef softface_outputs_skin_output_h
#define softface_outputs_skin_output_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/mapping/skin_mapping.h>
#include <softface/validation/distances.h>

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Subsection "Skin": the dense skin surface that every model's prediction
   * is mapped onto (Mollemans et al. 2007, Sec. 3.4), and the post-operative
   * skin it is measured against (paper, Sec. 3.5).
   */
  struct SkinParameters
  {
    static void
    declare_parameters(ParameterHandler &prm);
    /// Relative files are taken from @p input_directory; @p patient_skin is
    /// the skin the patient pipeline made (empty for other scenes).
    void
    parse_parameters(ParameterHandler  &prm,
                     const std::string &input_directory,
                     const std::string &patient_skin);

    /// Does a 'Post-operative skin' of @p file name a truth scene (a .prm
    /// whose run makes the skin) rather than a surface?
    static bool
    names_truth_scene(const std::string &file);

    std::string skin_surface; ///< empty: no skin
    std::string post_operative_skin;
    /// A scene whose run makes the post-operative skin (a phantom's truth):
    /// 'Post-operative skin' names a .prm file.
    std::string truth_scene;
    /// TPS-RPM correspondences of every measured point, the spline fitted
    /// to at most correspondence_fit_points of them.
    bool         correspondences           = true;
    unsigned int correspondence_fit_points = 10000;
    /// Also write each skin's signed distances as CSV (for scripts).
    bool                                write_distances = false;
    std::set<types::boundary_id>        mesh_skin_boundary_ids;
    std::vector<SurfaceMapping::Method> methods;
    SurfaceMapping::Parameters          mapping;
    Validation::Mask                    mask;
  };

  /**
   * The predicted skins of a run: step A of each mapping once, then for
   * every model step B, its skin as PLY and VTP (displacement and, with a
   * post-operative skin, the signed distance to it, for a -3..3 mm colour
   * map in ParaView) and the distance statistics, into skin.csv and a table.
   */
  class SkinOutput
  {
  public:
    /// Reads the skins and runs step A; progress and figures on @p out.
    SkinOutput(const SkinParameters &parameters,
               const Scene          &scene,
               const std::string    &directory,
               std::ostream         &out);

    /// Step B for one model's displacement (on the scene's layout), its
    /// skin files and statistics.
    void
    add_model(const std::string    &model,
              const Scene          &scene,
              const Vector<double> &displacement);

    /// Put the rows in the order of @p labels (the runs' labels as the
    /// scene lists the models; they are added in the order the models run).
    void
    order_rows(const std::vector<std::string> &labels);

    /// skin.csv and the table on @p out.
    void
    write(std::ostream &out) const;

    /// The dense skin at rest, and the post-operative skin (empty without
    /// one).
    const SurfaceMapping::Surface &
    skin_surface() const
    {
      return skin;
    }
    const SurfaceMapping::Surface &
    post_operative_surface() const
    {
      return post_operative;
    }

    /// The weights of mapping @p k (step A's result).
    const SurfaceMapping::SkinMapping &
    mapping(const unsigned int k = 0) const
    {
      return mappings[k];
    }

    /// Step B of the first mapping: @p displacement (on the scene's layout)
    /// at every skin point.
    void
    map(const Scene               &scene,
        const Vector<double>      &displacement,
        std::vector<Tensor<1, 3>> &skin_displacement,
        const unsigned int         mapping = 0) const;

  private:
    struct Row
    {
      std::string            model;
      SurfaceMapping::Method method;
      double                 step_b_seconds   = 0.;
      double                 max_displacement = 0.;
      bool                   measured         = false;
      Validation::Statistics distances;
      /// Distances between TPS-RPM correspondences (paper, Sec. 3.5.1).
      bool                   corresponded = false;
      Validation::Statistics correspondence;
      unsigned int           correspondence_points  = 0;
      double                 correspondence_seconds = 0.;
      /// Exact correspondences (a truth that moved the same skin points):
      /// |predicted - true| and its component along the post-operative
      /// normal.
      bool                   exact = false;
      Validation::Statistics exact_distances;
      Validation::Statistics exact_normal;
    };

    /// Whether the truth scene that made the post-operative skin moved the
    /// same skin points (its skin_preoperative.ply equals this skin): if
    /// so, fills exact_normals; says which on @p out.
    void
    find_exact_correspondences(std::ostream &out);

    /// TPS-RPM from the measured region of @p predicted to the
    /// post-operative surface; fills the row's correspondence and, per skin
    /// point, @p distance (NaN where no correspondence counts: outside the
    /// measured region or beyond the post-operative skin's rim) and
    /// @p offset, the vector from the predicted point to its partner (3 per
    /// point, NaN likewise).
    void
    correspond(const SurfaceMapping::Surface &predicted,
               const std::vector<bool>       &in_reach,
               Row                           &row,
               std::vector<double>           &distance,
               std::vector<double>           &offset) const;

    const SkinParameters   &parameters;
    std::string             directory;
    SurfaceMapping::Surface skin;
    SurfaceMapping::Surface post_operative;
    /// Outward unit normals at the post-operative skin's points, if the
    /// truth that made it moved the same points as this skin's (exact
    /// correspondences: point i of the one is point i of the other);
    /// empty otherwise.
    std::vector<Tensor<1, 3>>                exact_normals;
    std::vector<SurfaceMapping::SkinMapping> mappings;
    std::vector<double>                      step_a_seconds;
    std::vector<Row>                         rows;
  };
} // namespace softface

#endif

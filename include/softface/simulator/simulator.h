#ifndef softface_simulator_simulator_h
#define softface_simulator_simulator_h

#include <deal.II/base/parameter_handler.h>

#include <softface/core/planning_list.h>
#include <softface/core/scene.h>
#include <softface/models/interface.h>
#include <softface/outputs/report.h>

#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  class SkinOutput;

  using namespace dealii;

  /**
   * Runs one scene file: parse it, build the scene, turn each of its plans
   * into join-point displacements, run every selected model on them (one
   * setup, then a solve or a response-basis combination per plan), report
   * them side by side and write the outputs. A model that fails is
   * reported with its reason and the others still run.
   */
  class Simulator
  {
  public:
    Simulator();
    ~Simulator();

    /**
     * Declare every parameter. The Segment and Motion subsections depend on
     * the names a file lists, so a file is read twice: once tolerantly for
     * those names, then strictly with everything declared.
     */
    static void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &segment_names,
                       const std::vector<std::string> &moved_segments,
                       const std::vector<std::string> &cut_names  = {},
                       const std::vector<std::string> &plan_names = {});

    /// Fill @p prm from @p filename (both passes).
    static void
    read_parameters(const std::string &filename, ParameterHandler &prm);

    /// The documented default parameter file.
    static void
    print_default_parameters(std::ostream &out);

    /**
     * Run the scene in @p filename: progress and the table go to @p out,
     * warnings and model errors to @p err. Returns the process exit code: 0,
     * or 1 if a model failed. Errors in the input are thrown as Error.
     */
    int
    run(const std::string &filename,
        std::ostream      &out = std::cout,
        std::ostream      &err = std::cerr);

    /**
     * What run() does before the models solve: read the parameters, build
     * the scene with its effects, the plans and their join displacements,
     * create the models (not set up), read the skin and run step A of its
     * mappings, and create the output folder; progress on @p out. Errors in
     * the input are thrown as Error. (softface serve starts here.)
     */
    void
    prepare(const std::string &filename, std::ostream &out = std::cout);

    /// After prepare(): the parameters read, the plans, the models (created,
    /// not set up) and the skin (nullptr without one, and on MPI ranks other
    /// than 0, where rank 0 maps the skins for all).
    ParameterHandler &
    parameters();
    const PlanningList &
    plannings() const;
    std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>> &
    models();
    SkinOutput *
    skin() const;

    /// After run(): the scene, every model's run and the reference model.
    const Scene &
    scene() const;
    const std::vector<Report::ModelRun> &
    runs() const;
    const std::string &
    reference_model() const;

  private:
    /// The steps of prepare(), in order.
    void
    create_plugins(const std::string &filename);
    /// Returns the name of a model or effect that needs the scene's cells
    /// on every rank (empty if none does).
    std::string
    build_scene(const std::string &filename, std::ostream &out);
    void
    describe_scene(const std::string &needs_cells,
                   double             seconds,
                   std::ostream      &out) const;
    void
    prepare_skin(const std::string &filename, std::ostream &out);
    void
    prepare_outputs(std::ostream &out);
    void
    write_inputs(const std::string &filename, std::ostream &out);
    void
    check_planning_scale(const std::string &filename) const;

    /// After each plan a model answered: to every output asked for.
    void
    hand_to_outputs(const Report::ModelRun &run,
                    Models::Interface      &model,
                    bool                    from_basis);
    /// Every output asked for writes its files.
    void
    write_outputs(std::ostream &out);
    /// The outputs written, the wall time and the peak memory.
    void
    print_closing(std::ostream &out) const;

    struct Prepared;
    // The scene outlives what is prepared on it (models hold DoF handlers
    // on its triangulation): declared first, destroyed last.
    std::unique_ptr<Scene>        the_scene;
    std::unique_ptr<Prepared>     state;
    std::vector<Report::ModelRun> model_runs;
    std::string                   reference;
  };
} // namespace softface

#endif

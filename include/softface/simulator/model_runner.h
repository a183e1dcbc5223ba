#ifndef softface_simulator_model_runner_h
#define softface_simulator_model_runner_h

#include <deal.II/lac/vector.h>

#include <softface/core/planning_list.h>
#include <softface/core/scene.h>
#include <softface/models/interface.h>
#include <softface/models/response_basis.h>
#include <softface/outputs/report.h>

#include <exception>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  /**
   * Runs a scene's models on its plans, one model after the other: one
   * setup per model, then for each plan a solve or, for a model linear in
   * the motion when there are more plans than the basis costs solves, a
   * combination of its response basis. A model that fails (no convergence,
   * a motion it cannot follow) is recorded with its reason and the others
   * still run. On several MPI ranks every rank runs alike and the ranks
   * agree on every failure (RankPolicy).
   */
  class ModelRunner
  {
  public:
    /**
     * Called after each plan a model answered, with the model still alive
     * and whether the answer came from its response basis (the skins and
     * the evaluation points take the answer there). Collective.
     */
    using AfterRun = std::function<
      void(const Report::ModelRun &, Models::Interface &, bool from_basis)>;

    /// @p layout: on several MPI ranks, the partition the distributed
    /// models share (nullptr on one rank).
    ModelRunner(Scene                                          &scene,
                const PlanningList                             &plannings,
                const std::shared_ptr<SharedDistributedLayout> &layout,
                std::ostream                                   &out,
                std::ostream                                   &err,
                AfterRun                                        after_run);

    /**
     * Run every model of @p models, each freed once it has run, appending
     * one run per model and plan to @p runs in the order of @p models
     * (model after model). A model runs after the models whose answers it
     * takes (run_order()), so that no result depends on the order of
     * Models/Models. Returns how many runs failed.
     */
    unsigned int
    run_all(
      std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>>
                                    &models,
      std::vector<Report::ModelRun> &runs);

  private:
    /**
     * The order the models run in: each after the model its
     * converged_equivalent() names (whose answer measures its precision)
     * and, if it is not linear in the motion, after the models that are
     * (whose answers start the nonlinear models); otherwise as listed.
     */
    std::vector<unsigned int>
    run_order(const std::vector<
              std::pair<std::string, std::unique_ptr<Models::Interface>>>
                &models) const;

    /// What a model's setup leaves for its plans.
    struct Setup
    {
      Models::ResponseBasis basis;
      bool                  use_basis  = false;
      double                basis_time = 0.;
      Models::Statistics    after_setup;
    };

    /// Set @p model up (and its response basis if it pays); the failure
    /// it threw, if any.
    std::exception_ptr
    set_up(Models::Interface &model, const std::string &tag, Setup &setup);

    /// Plan @p p: solved or combined, checked, handed to the outputs.
    Report::ModelRun
    run_plan(const std::string &name,
             Models::Interface &model,
             unsigned int       p,
             const std::string &tag,
             Setup             &setup);

    /// Plan @p p's answer as a combination of the response basis.
    void
    combine(Setup &setup, unsigned int p, Report::ModelRun &run) const;

    /// Plan @p p solved by @p model, with what earlier models answered.
    void
    solve(Models::Interface &model, unsigned int p, Report::ModelRun &run);

    /**
     * The answer of a model that ran earlier to plan @p p that @p wanted
     * accepts (every model that ran has a run per plan, in order), or
     * nullptr.
     */
    const Vector<double> *
    earlier_answer(
      unsigned int                                         p,
      const std::function<bool(const Report::ModelRun &)> &wanted) const;

    /**
     * Mark @p run failed with @p e's message, said at @p where (empty:
     * said once already, for the model's first plan). Rethrows what may be
     * one rank's failure (RankPolicy::is_every_ranks_failure): call it in a
     * catch block.
     */
    void
    record_failure(Report::ModelRun     &run,
                   const std::string    &where,
                   const std::exception &e);

    /// The name of plan @p p in a run's label (none for a single plan).
    std::string
    plan_name(unsigned int p) const;

    Scene                                   &scene;
    const PlanningList                      &plannings;
    std::shared_ptr<SharedDistributedLayout> layout;
    std::ostream                            &out;
    std::ostream                            &err;
    AfterRun                                 after_run;
    std::vector<Report::ModelRun>           *runs = nullptr;
    /// Where this run_all() began appending to *runs.
    std::size_t  first_run = 0;
    unsigned int n_failed  = 0;
  };
} // namespace softface

#endif

// The scene's models run on its plans (simulator): setup, response basis,
// solve or combination per plan, the hand-offs between models, failures.

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <softface/core/displacement.h>
#include <softface/core/error.h>
#include <softface/simulator/model_runner.h>
#include <softface/simulator/rank_policy.h>

#include <cmath>
#include <iomanip>
#include <iterator>

namespace softface
{
  ModelRunner::ModelRunner(
    Scene                                          &scene,
    const PlanningList                             &plannings,
    const std::shared_ptr<SharedDistributedLayout> &layout,
    std::ostream                                   &out,
    std::ostream                                   &err,
    AfterRun                                        after_run)
      : scene(scene)
      , plannings(plannings)
      , layout(layout)
      , out(out)
      , err(err)
      , after_run(std::move(after_run))
  {}

  unsigned int
  ModelRunner::run_all(
    std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>>
                                  &models,
    std::vector<Report::ModelRun> &model_runs)
  {
    runs                       = &model_runs;
    n_failed                   = 0;
    first_run                  = model_runs.size();
    const unsigned int n_plans = plannings.plans.size();
    const auto         order   = run_order(models);
    for (unsigned int k = 0; k < order.size(); ++k)
      {
        auto &[name, model]   = models[order[k]];
        const std::string tag = "  [" + std::to_string(k + 1) + '/' +
                                std::to_string(models.size()) + "] " + name +
                                ": ";
        Setup                    setup;
        const std::exception_ptr setup_error = set_up(*model, tag, setup);
        RankPolicy::agree_on_failure(setup_error != nullptr, name + "'s setup");
        if (setup_error)
          {
            // Setup failed: so does every plan.
            try
              {
                std::rethrow_exception(setup_error);
              }
            catch (const std::exception &e)
              {
                for (unsigned int p = 0; p < n_plans; ++p)
                  {
                    Report::ModelRun run;
                    run.model    = name;
                    run.planning = plan_name(p);
                    record_failure(run, p == 0 ? tag : std::string(), e);
                    runs->push_back(std::move(run));
                  }
              }
          }
        else
          for (unsigned int p = 0; p < n_plans; ++p)
            runs->push_back(run_plan(name, *model, p, tag, setup));
        // The model's memory is freed once it has run; the peak stays.
        model.reset();
      }

    // Reported in the order of Models/Models.
    std::vector<Report::ModelRun> ran(
      std::make_move_iterator(model_runs.begin() + first_run),
      std::make_move_iterator(model_runs.end()));
    for (unsigned int k = 0; k < order.size(); ++k)
      for (unsigned int p = 0; p < n_plans; ++p)
        model_runs[first_run + order[k] * n_plans + p] =
          std::move(ran[k * n_plans + p]);
    return n_failed;
  }

  std::vector<unsigned int>
  ModelRunner::run_order(
    const std::vector<
      std::pair<std::string, std::unique_ptr<Models::Interface>>> &models) const
  {
    // Model m waits for the model that solves its equations exactly (its
    // answer measures m's precision) and, unless m is linear in the motion,
    // for every model that is (their answers are the nonlinear models'
    // start); among the models whose turn it is, the first listed runs.
    const unsigned int n = models.size();
    std::vector<bool>  linear(n);
    for (unsigned int m = 0; m < n; ++m)
      linear[m] = models[m].second->linear_in_motion(scene);
    const auto waits_for = [&](const unsigned int m, const unsigned int o) {
      return o != m &&
             (models[o].first == models[m].second->converged_equivalent() ||
              (linear[o] && !linear[m]));
    };
    std::vector<unsigned int> order;
    std::vector<bool>         done(n, false);
    while (order.size() < n)
      {
        unsigned int next = n;
        for (unsigned int m = 0; m < n && next == n; ++m)
          {
            bool ready = !done[m];
            for (unsigned int o = 0; o < n && ready; ++o)
              ready = done[o] || !waits_for(m, o);
            if (ready)
              next = m;
          }
        // Models that wait for each other run in the listed order.
        if (next == n)
          for (unsigned int m = 0; m < n && next == n; ++m)
            if (!done[m])
              next = m;
        done[next] = true;
        order.push_back(next);
      }
    return order;
  }

  std::exception_ptr
  ModelRunner::set_up(Models::Interface &model,
                      const std::string &tag,
                      Setup             &setup)
  {
    try
      {
        Models::RunContext context;
        context.progress = &out;
        context.layout   = layout;
        model.setup(scene, context);
        setup.after_setup = model.statistics();
        out << tag << "setup " << setup.after_setup.setup_time << " s"
            << std::endl;
        // A model linear in the motion builds its response basis when the
        // plans outnumber the solves the basis costs (or when asked to).
        const auto         moved = plannings.plans[0].planning.moved_segments();
        const unsigned int n_basis_solves =
          Models::ResponseBasis::n_solves(scene, moved.size());
        setup.use_basis = model.linear_in_motion(scene) &&
                          (plannings.basis == PlanningList::Basis::always ||
                           (plannings.basis == PlanningList::Basis::automatic &&
                            plannings.plans.size() > n_basis_solves));
        if (setup.use_basis)
          {
            Timer timer;
            setup.basis.build(model, scene, moved);
            setup.basis_time = timer.wall_time();
            out << tag << "response basis " << setup.basis_time << " s ("
                << n_basis_solves << " solves, " << std::setprecision(3)
                << setup.basis.memory_mb() << " MB)" << std::endl;
          }
      }
    catch (const std::exception &e)
      {
        if (!RankPolicy::is_every_ranks_failure(e))
          throw; // main() ends the job
        return std::current_exception();
      }
    return nullptr;
  }

  Report::ModelRun
  ModelRunner::run_plan(const std::string &name,
                        Models::Interface &model,
                        const unsigned int p,
                        const std::string &tag,
                        Setup             &setup)
  {
    const unsigned int n_plans = plannings.plans.size();
    Report::ModelRun   run;
    run.model               = name;
    run.planning            = plan_name(p);
    run.basis_time          = setup.basis_time;
    const std::string where = n_plans > 1 ?
                                tag + "plan " + std::to_string(p + 1) + '/' +
                                  std::to_string(n_plans) + " '" +
                                  plannings.plans[p].name + "': " :
                                tag;
    try
      {
        if (setup.use_basis)
          combine(setup, p, run);
        else
          solve(model, p, run);
        // Overflowing inputs (moduli or loads far out of range) or a solve
        // that broke down must not pass as an answer.
        for (const double value : run.displacement)
          if (!std::isfinite(value))
            throw Error(name + ": the displacement is not finite (NaN or "
                               "infinite): the solve broke down or the inputs "
                               "(moduli, loads) are far out of range.");
        run.max_displacement = Displacement::max_norm(scene, run.displacement);
        out << where << (setup.use_basis ? "combination " : "solve ")
            << run.statistics.solve_time << " s" << std::endl;
        for (const auto &warning : run.statistics.warnings)
          err << "softface: warning: " << run.label() << ": " << warning
              << std::endl;
        after_run(run, model, setup.use_basis);
      }
    catch (const std::exception &e)
      {
        record_failure(run, where, e);
      }
    Utilities::System::MemoryStats memory;
    Utilities::System::get_memory_stats(memory);
    run.peak_memory_mb = memory.VmHWM / 1024.;
    if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
      {
        RankPolicy::agree_on_failure(run.failed, run.label() + "'s solve");
        RankPolicy::take_slowest_rank(run);
      }
    return run;
  }

  void
  ModelRunner::combine(Setup             &setup,
                       const unsigned int p,
                       Report::ModelRun  &run) const
  {
    Timer timer;
    setup.basis.combine(plannings.plans[p].planning, run.displacement);
    run.statistics            = setup.after_setup;
    run.statistics.solve_time = timer.wall_time();
    run.statistics.residual   = setup.basis.largest_residual;
    run.statistics.phases.emplace_back("response basis", setup.basis_time);
    run.statistics.phases.emplace_back("combination",
                                       run.statistics.solve_time);
    run.statistics.details.push_back(
      {"basis iterations", double(setup.basis.total_iterations), "", ""});
    run.statistics.details.push_back(
      {"basis memory", setup.basis.memory_mb(), "", "MB"});
    for (const auto &warning : setup.basis.warnings)
      run.statistics.warnings.push_back("response basis: " + warning);
  }

  void
  ModelRunner::solve(Models::Interface &model,
                     const unsigned int p,
                     Report::ModelRun  &run)
  {
    const auto         &plan = plannings.plans[p];
    Models::PlanContext context;
    context.load_path = [&plan, this](const double load) {
      return plan.planning.prescribed_displacement(scene, load);
    };
    // A model that ran this plan from its response basis offers its answer
    // as a start (the nonlinear models take it); the model that solves this
    // one's equations exactly, its answer.
    context.initial_guess = earlier_answer(p, [](const Report::ModelRun &r) {
      return r.basis_time > 0.;
    });
    const std::string equivalent = model.converged_equivalent();
    context.converged_answer =
      earlier_answer(p, [&](const Report::ModelRun &r) {
        return r.model == equivalent;
      });
    model.solve(plan.planning.prescribed_displacement(scene),
                run.displacement,
                context);
    run.statistics = model.statistics();
  }

  const Vector<double> *
  ModelRunner::earlier_answer(
    const unsigned int                                   p,
    const std::function<bool(const Report::ModelRun &)> &wanted) const
  {
    const unsigned int n_plans = plannings.plans.size();
    for (std::size_t r = first_run + p; r < runs->size(); r += n_plans)
      if (!(*runs)[r].failed && wanted((*runs)[r]))
        return &(*runs)[r].displacement;
    return nullptr;
  }

  void
  ModelRunner::record_failure(Report::ModelRun     &run,
                              const std::string    &where,
                              const std::exception &e)
  {
    if (!RankPolicy::is_every_ranks_failure(e))
      throw; // main() ends the job
    run.failed = true;
    run.error  = error_message(e);
    run.displacement.reinit(0);
    ++n_failed;
    if (where.empty())
      return;
    out << where << "failed" << std::endl;
    err << "softface: error: " + run.error + '\n' << std::flush;
  }

  std::string
  ModelRunner::plan_name(const unsigned int p) const
  {
    return plannings.plans.size() > 1 ? plannings.plans[p].name : std::string();
  }
} // namespace softface

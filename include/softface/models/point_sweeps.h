#ifndef softface_models_point_sweeps_h
#define softface_models_point_sweeps_h

#include <softface/core/error.h>
#include <softface/core/point_mesh.h>
#include <softface/core/scene.h>
#include <softface/models/active_set.h>
#include <softface/models/block_colouring.h>
#include <softface/models/point_exchange.h>

#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  /**
   * What the local updates of a sweep found. Each block of a sweep keeps
   * its own (a block runs on one thread); the sweep folds the blocks', and
   * on several MPI ranks the ranks'.
   */
  struct SweepTally
  {
    /// The largest step a point took (mm).
    double largest_step = 0.;
    /// Every point the sweep updated has stopped by its own criterion.
    bool all_stopped = true;
    /// Nonzero if an update failed: the length of its step, or infinity
    /// for a step that is not a number. The failed update ends its block;
    /// the model reports it after the sweep (a thread does not throw).
    double failure = 0.;
    /// Updates the model did not take (mass spring: each would have
    /// inverted a tetrahedron). This rank's, not summed over the ranks.
    unsigned long long held_back = 0;
  };

  /// What a model decides once a sweep is done.
  enum class SweepDecision
  {
    /// Sweep the points queued for the next sweep.
    go_on,
    /// The solve (or load step) is done.
    stop,
    /// Not done yet, although the stop criterion said so: every point
    /// sweeps on.
    sweep_every_point
  };

  /**
   * What the local updates of both point models hold alike (a model's
   * class for PointSweeps derives from it): the scene's nodal body force,
   * the stop threshold that is also the wake threshold, and nothing to do
   * after a sweep in Gauss-Seidel order.
   */
  class PointLocalUpdates
  {
  public:
    PointLocalUpdates(const Scene &scene, const double stop_threshold)
        : load(scene.has_body_force() ? scene.effects.body_force.begin() :
                                        nullptr)
        , stop_threshold(stop_threshold)
    {}

    /// The step (mm per sweep) below which a point stops.
    double
    threshold() const
    {
      return stop_threshold;
    }

    void
    finish_sweep(const std::vector<unsigned int> &)
    {}

  protected:
    /// The external nodal forces (gravity: SceneEffects::body_force), 3
    /// per point in the serial numbering; nullptr without a body force.
    const double *const load;
    double              stop_threshold;
  };

  /**
   * The sweeps of a point model (mass tensor, mass spring): Gauss-Seidel
   * (or Jacobi) sweeps of local updates until the model's stop criterion
   * says stop. What the two models share is here once: the order of the
   * updates and what may run at once (BlockColouring: the blocks of a
   * colour on the threads, the colours in turn), the points a sweep visits
   * (ActiveSet: the dynamic cut-out and active set of Mollemans et al. 2007,
   * Sec. 2.2 and 2.3.3), the exchange of the colours' values between MPI ranks
   * (PointExchange) with every decision to go on or stop taken on global
   * figures, the sweep count and its limit, the progress lines and the ranks'
   * figures for the report. A model brings its local update and its decision
   * after each sweep, as a class with these members (called as a template, so
   * that the local update inlines into the sweep's loop; PointLocalUpdates
   * gives finish_sweep() and threshold()):
   *
   *   // Update point j; queue what its step wakes in @p queued (queue(),
   *   // queue_neighbours()) and add to @p tally. False: the update
   *   // failed (tally.failure), and its block stops.
   *   bool update(unsigned int j, SweepTally &tally,
   *               std::vector<unsigned int> &queued);
   *   // After the blocks of a sweep (Jacobi order writes its values here).
   *   void finish_sweep(const std::vector<unsigned int> &points);
   *   // A ghost that moved by more than this wakes its neighbours here
   *   // (unless Settings::wake_on_any_change).
   *   double threshold() const;
   *   // The error when a sweep more would pass Settings::max_sweeps, with
   *   // the points of that sweep. Collective.
   *   std::string too_many_sweeps(const PointSweeps &sweeps,
   *                               const std::vector<unsigned int> &points);
   *   // After each sweep, with the tally on every rank: go on or stop,
   *   // where @p stop_proposed says what the active set (or, without it,
   *   // every point) asks for. Collective.
   *   SweepDecision after_sweep(const PointSweeps &sweeps,
   *                             const SweepTally &tally, bool stop_proposed);
   */
  class PointSweeps
  {
  public:
    struct Settings
    {
      /// The points' values, 3 doubles per point in the serial numbering
      /// (what the ranks exchange).
      double      *values     = nullptr;
      unsigned int max_sweeps = 1;
      /// Visit only the points queued for a sweep; false: every point this
      /// rank updates, until the model stops.
      bool active_set = true;
      /// Gauss-Seidel order: the ranks exchange after each colour; false
      /// (Jacobi order): after the sweep.
      bool gauss_seidel = true;
      /// A ghost that changed at all wakes its neighbours (the mass spring
      /// model), not only one that moved by more than the threshold.
      bool wake_on_any_change = false;
    };

    /// Sweeps over @p mesh's points in @p colouring's order, the points of
    /// @p exchange's blocks on several MPI ranks (nullptr: one rank).
    PointSweeps(const PointMesh      &mesh,
                const BlockColouring &colouring,
                const PointExchange  *exchange,
                const Settings       &settings,
                std::ostream         *progress);

    /// Another exchange (the mass spring model shares its blocks again
    /// between load steps): the points this rank updates change with it.
    void
    use_exchange(const PointExchange *exchange);

    /// Does this rank update point @p j (a free point, on several ranks one
    /// it owns)?
    bool
    updates(const unsigned int j) const
    {
      return mine[j];
    }

    /// Visit point @p j in the next sweep (outside a sweep).
    void
    queue(const unsigned int j)
    {
      active.queue(j);
    }
    /// The same from a local update, into its block's @p queued.
    void
    queue(const unsigned int j, std::vector<unsigned int> &queued)
    {
      active.queue(j, queued);
    }
    /// From a local update: visit the neighbours of @p j that this rank
    /// updates (their force has changed).
    void
    queue_neighbours(const unsigned int j, std::vector<unsigned int> &queued)
    {
      for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
        if (mine[neighbour[i]])
          active.queue(neighbour[i], queued);
    }

    /**
     * Sweep the points queued (without the active set: every point this
     * rank updates) until @p model stops, or throw its too_many_sweeps().
     * @p note follows the sweep number in the progress lines. Collective.
     */
    template <typename Model>
    void
    run(Model &model, const std::string &note = "");

    /// The points of the sweep that runs next (during after_sweep()) or
    /// last.
    const std::vector<unsigned int> &
    points() const
    {
      return settings.active_set ? active.current() : every_point;
    }

    /// Sweeps so far, on every rank the same.
    unsigned int
    n_sweeps() const
    {
      return sweep_count;
    }
    /// This rank's point updates and updates held back so far.
    unsigned long long
    n_point_updates() const
    {
      return point_updates;
    }
    unsigned long long
    n_held_back() const
    {
      return held_back;
    }

    /// This rank's updates in each block since the last clear, as the
    /// weights by which PointExchange shares the blocks.
    std::vector<double> &
    block_updates()
    {
      return updates_in_block;
    }

    /// @p local summed, or its largest value, over the ranks. Collective.
    unsigned long long
    sum(const unsigned long long local) const
    {
      return sum_over_ranks(exchange, local);
    }
    double
    max(const double local) const
    {
      return max_over_ranks(exchange, local);
    }

    /// On several ranks, the figures that say how evenly they shared the
    /// work (none on one). Collective.
    std::vector<std::pair<std::string, double>>
    rank_figures() const;

  private:
    /// One sweep over @p points: every block's updates, the colours in turn.
    template <typename Model>
    SweepTally
    sweep(const std::vector<unsigned int> &points, Model &model);

    /// The blocks' tallies folded, and the points they queued taken over.
    SweepTally
    fold_blocks();
    /// After a colour (or, in Jacobi order, the sweep): the exchange of
    /// the values between the ranks, which wakes the ghosts' neighbours.
    void
    exchange_colour(const unsigned int colour,
                    const std::size_t  n_updated,
                    const double       threshold);
    /// The decisions of a sweep taken on every rank's figures. Collective.
    void
    reduce(SweepTally &tally, bool &more) const;
    /// Every 1000 sweeps, the number of active points. Collective.
    void
    report_progress(const std::size_t n_points, const std::string &note) const;

    const std::vector<unsigned int> &row_start;
    const std::vector<unsigned int> &neighbour;
    const PointMesh                 &mesh;
    const BlockColouring            &colouring;
    const PointExchange             *exchange;
    const Settings                   settings;
    std::ostream *const              progress;

    std::vector<char>         mine;
    std::vector<unsigned int> every_point;
    ActiveSet                 active;

    unsigned int       sweep_count   = 0;
    unsigned long long point_updates = 0;
    unsigned long long held_back     = 0;

    // Per block: what its updates found, the points they queued (a block
    // runs on one thread) and how many it made.
    std::vector<SweepTally>                block_tally;
    std::vector<std::vector<unsigned int>> block_queued;
    std::vector<double>                    updates_in_block;
    /// Ghost points that moved in an exchange.
    std::vector<unsigned int> moved_ghosts;
    /// The ranks' updates colour by colour.
    ColourUpdates colour_updates;
  };


  template <typename Model>
  void
  PointSweeps::run(Model &model, const std::string &note)
  {
    active.next_sweep();
    bool go_on = sum(points().size()) > 0;
    while (go_on)
      {
        const std::vector<unsigned int> &current = points();
        if (sweep_count == settings.max_sweeps)
          throw Error(model.too_many_sweeps(*this, current));
        ++sweep_count;
        point_updates += current.size();
        if (sweep_count % 1000 == 0)
          report_progress(current.size(), note);

        SweepTally tally = sweep(current, model);
        model.finish_sweep(current);
        if (!settings.gauss_seidel && exchange != nullptr)
          exchange_colour(numbers::invalid_unsigned_int,
                          current.size(),
                          model.threshold());
        // (current is the active set's: from here on the next sweep's.)
        bool more = settings.active_set && !active.next_sweep().empty();
        reduce(tally, more);

        switch (model.after_sweep(
          *this, tally, settings.active_set ? !more : tally.all_stopped))
          {
            case SweepDecision::go_on:
              break;
            case SweepDecision::stop:
              go_on = false;
              break;
            case SweepDecision::sweep_every_point:
              for (const unsigned int j : every_point)
                active.queue(j);
              active.next_sweep();
              break;
          }
      }
  }


  template <typename Model>
  SweepTally
  PointSweeps::sweep(const std::vector<unsigned int> &points, Model &model)
  {
    const double threshold = model.threshold();
    colouring.sweep(
      points,
      [&](const unsigned int b,
          const std::size_t  begin,
          const std::size_t  end) {
        std::vector<unsigned int> &queued = block_queued[b];
        updates_in_block[b] += end - begin;
        SweepTally tally;
        for (std::size_t q = begin; q < end; ++q)
          if (!model.update(points[q], tally, queued))
            break;
        block_tally[b] = tally;
      },
      exchange != nullptr && settings.gauss_seidel ?
        std::function<void(unsigned int, std::size_t)>(
          [&](const unsigned int c, const std::size_t n_updated) {
            exchange_colour(c, n_updated, threshold);
          }) :
        std::function<void(unsigned int, std::size_t)>());
    return fold_blocks();
  }
} // namespace softface

#endif

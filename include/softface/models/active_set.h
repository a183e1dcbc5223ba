#ifndef softface_active_set_h
#define softface_active_set_h

#include <algorithm>
#include <atomic>
#include <vector>

namespace softface
{
  /**
   * The points a local solver visits in its next sweep: the dynamic
   * cut-out (Mollemans et al. 2007, Sec. 2.2) and active set (Sec. 2.3.3)
   * revisit only points whose force can have changed. A point is queued at most
   * once per sweep, and a sweep visits its points in ascending (memory) order,
   * so that neighbours share cache lines once the model no longer fits in
   * cache.
   */
  class ActiveSet
  {
  public:
    explicit ActiveSet(const unsigned int n_points)
        : queued_in(n_points) // zero: no sweep's stamp
    {}

    /// Visit @p point in the next sweep (again queuing it does nothing).
    void
    queue(const unsigned int point)
    {
      if (queued_in[point].load(std::memory_order_relaxed) != stamp)
        {
          queued_in[point].store(stamp, std::memory_order_relaxed);
          queued.push_back(point);
        }
    }

    /**
     * The same from one of several threads sweeping at once: the point goes
     * to that thread's @p list (a point queued by several lands in one),
     * which add() hands over once the threads are done.
     */
    void
    queue(const unsigned int point, std::vector<unsigned int> &list)
    {
      // A plain read first: most points are queued already (a point is
      // the neighbour of a dozen that move), and the exchange, a locked
      // instruction, took a fifth of the mass tensor's sweeps. The exchange
      // still decides which thread lists a point.
      if (queued_in[point].load(std::memory_order_relaxed) != stamp &&
          queued_in[point].exchange(stamp, std::memory_order_relaxed) != stamp)
        list.push_back(point);
    }

    /// Take over the points a thread queued (and empty its @p list).
    void
    add(std::vector<unsigned int> &list)
    {
      queued.insert(queued.end(), list.begin(), list.end());
      list.clear();
    }

    /// Start the next sweep: the queued points become current, ascending.
    const std::vector<unsigned int> &
    next_sweep()
    {
      // A long list is rebuilt by scanning the marks, a short one sorted.
      if (queued.size() > queued_in.size() / 32)
        {
          queued.clear();
          for (unsigned int j = 0; j < queued_in.size(); ++j)
            if (queued_in[j].load(std::memory_order_relaxed) == stamp)
              queued.push_back(j);
        }
      else
        std::sort(queued.begin(), queued.end());
      current_points.swap(queued);
      queued.clear();
      ++stamp;
      return current_points;
    }

    /// The points of the current sweep.
    const std::vector<unsigned int> &
    current() const
    {
      return current_points;
    }

  private:
    // The sweep stamp a point is queued for (atomic: threads queue at once).
    std::vector<std::atomic<unsigned int>> queued_in;
    std::vector<unsigned int>              queued;
    std::vector<unsigned int>              current_points;
    unsigned int                           stamp = 1;
  };
} // namespace softface

#endif

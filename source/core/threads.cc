// Threads: one BLAS thread per process, and deal.II's task scheduler for
// softface's own loops (issue 16).

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/parallel.h>

#include <softface/core/threads.h>

#include <algorithm>
#include <cstdlib>

// Present only when the BLAS in use is OpenBLAS.
extern "C" void
openblas_set_num_threads(int) __attribute__((weak));

namespace softface
{
  void
  limit_blas_threads()
  {
    if (openblas_set_num_threads != nullptr &&
        std::getenv("OPENBLAS_NUM_THREADS") == nullptr)
      openblas_set_num_threads(1);
  }

  namespace Threads
  {
    void
    set_limit(const unsigned int n)
    {
      // More threads than cores only split the work finer (a scene asking
      // for 100000 made as many assembly parts).
      const unsigned int cores = dealii::MultithreadInfo::n_cores();
      dealii::MultithreadInfo::set_thread_limit(
        n == 0 ? dealii::numbers::invalid_unsigned_int : std::min(n, cores));
    }

    unsigned int
    n_threads()
    {
      return dealii::MultithreadInfo::n_threads();
    }

    void
    run_tasks(const unsigned int                       n_tasks,
              const std::function<void(unsigned int)> &task)
    {
      if (n_threads() == 1 || n_tasks <= 1)
        {
          for (unsigned int i = 0; i < n_tasks; ++i)
            task(i);
          return;
        }
      // One task per grain: the tasks are few and large (a part of the
      // mesh), and TBB balances them over the threads.
      dealii::parallel::apply_to_subranges(
        0u,
        n_tasks,
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int i = begin; i < end; ++i)
            task(i);
        },
        1);
    }
  } // namespace Threads
} // namespace softface

// Threads: one BLAS thread per process, and deal.II's task scheduler for
// softface's own loops.

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/parallel.h>

#include <softface/core/threads.h>

#include <mpi.h>
#include <sched.h>

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
    namespace
    {
      // The MPI ranks on this machine (1 without MPI).
      unsigned int
      ranks_on_this_machine()
      {
        int initialised = 0;
        MPI_Initialized(&initialised);
        int size = 1;
        if (initialised)
          MPI_Comm_size(MPI_COMM_WORLD, &size);
        if (size == 1)
          return 1;
        MPI_Comm machine;
        MPI_Comm_split_type(
          MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &machine);
        MPI_Comm_size(machine, &size);
        MPI_Comm_free(&machine);
        return size;
      }

      // The cores this process may run on (a launcher or batch system that
      // binds it gives it fewer than the machine has).
      unsigned int
      cores_of_this_process()
      {
        const unsigned int cores = dealii::MultithreadInfo::n_cores();
        cpu_set_t          set;
        CPU_ZERO(&set);
        if (sched_getaffinity(0, sizeof(set), &set) != 0)
          return cores;
        return std::clamp<unsigned int>(CPU_COUNT(&set), 1, cores);
      }
    } // namespace

    void
    set_limit(const unsigned int n)
    {
      // More threads than cores only split the work finer (a scene asking
      // for 100000 made as many assembly parts); ranks on one machine share
      // its cores, and none uses more than it is bound to.
      const unsigned int cores = cores_of_this_process();
      const unsigned int share =
        std::max(1u,
                 dealii::MultithreadInfo::n_cores() / ranks_on_this_machine());
      dealii::MultithreadInfo::set_thread_limit(
        std::min(n == 0 ? share : n, cores));
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
      // One task per grain: TBB balances them over the threads (a point
      // model's blocks are 256 points, about 50 microseconds of work).
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

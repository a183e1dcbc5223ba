#ifndef softface_threads_h
#define softface_threads_h

#include <functional>

namespace softface
{
  /**
   * softface's own loops (assembly, the mass tensor and mass spring sweeps)
   * run on the threads of deal.II's task scheduler (TBB). BLAS does not:
   * OpenBLAS (under CHOLMOD) would start a thread per core, and its waiting
   * threads spin: two processes on two cores then ran the same
   * factorisation 20 times slower. This keeps OpenBLAS to one thread unless
   * OPENBLAS_NUM_THREADS says otherwise; with another BLAS it does nothing.
   */
  void
  limit_blas_threads();

  namespace Threads
  {
    /**
     * Use at most @p n threads (the scene's Models/Threads), no more than
     * there are cores; 0 means every core, shared among the MPI ranks on
     * this machine. The environment variable DEAL_II_NUM_THREADS, if set,
     * caps it. Collective when MPI runs several ranks.
     */
    void
    set_limit(unsigned int n);

    /// The number of threads softface's loops use.
    unsigned int
    n_threads();

    /**
     * Call @p task(i) for i = 0, ..., n_tasks - 1, on up to n_threads()
     * threads, and return when all are done. The tasks must not write what
     * another reads or writes; then the result does not depend on the
     * number of threads. With one thread, in order on this one.
     */
    void
    run_tasks(unsigned int                             n_tasks,
              const std::function<void(unsigned int)> &task);
  } // namespace Threads
} // namespace softface

#endif

#ifndef softface_threads_h
#define softface_threads_h

namespace softface
{
  /**
   * softface computes on one thread per process. OpenBLAS (under CHOLMOD)
   * would start a thread per core, and its waiting threads spin: two
   * processes on two cores then ran the same factorisation 20 times slower.
   * This keeps OpenBLAS to one thread unless OPENBLAS_NUM_THREADS says
   * otherwise; with another BLAS it does nothing.
   */
  void
  limit_blas_threads();
} // namespace softface

#endif

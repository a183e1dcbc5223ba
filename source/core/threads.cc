// One BLAS thread per process (core): OpenBLAS's spinning threads slowed the
// direct solver 10-20 times when two processes shared the two cores.

#include <softface/core/threads.h>

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
} // namespace softface

#ifndef softface_core_on_rank_0_h
#define softface_core_on_rank_0_h

#include <deal.II/base/mpi.h>

#include <functional>

namespace softface
{
  /**
   * Run @p work on rank 0 of @p communicator alone, for what one rank does
   * for all (the patient pipeline, which writes its stages; the
   * skin mapping and its files). A softface::Error it throws is thrown on
   * every rank, with rank 0's message, so that the ranks fail alike, as a
   * serial run would, and none is left waiting in a collective. Anything
   * else it throws stays rank 0's (main() then ends the job). Collective.
   */
  void
  on_rank_0(const MPI_Comm communicator, const std::function<void()> &work);
} // namespace softface

#endif

// What one MPI rank does for all, failing on every rank alike.
// See core/on_rank_0.h.

#include <softface/core/error.h>
#include <softface/core/on_rank_0.h>

#include <string>

namespace softface
{
  void
  on_rank_0(const MPI_Comm communicator, const std::function<void()> &work)
  {
    std::string message;
    bool        failed = false;
    if (dealii::Utilities::MPI::this_mpi_process(communicator) == 0)
      try
        {
          work();
        }
      catch (const Error &e)
        {
          failed  = true;
          message = e.what();
        }
    if (dealii::Utilities::MPI::n_mpi_processes(communicator) > 1)
      {
        failed  = dealii::Utilities::MPI::broadcast(communicator, failed);
        message = dealii::Utilities::MPI::broadcast(communicator, message);
      }
    if (failed)
      throw Error(message);
  }
} // namespace softface

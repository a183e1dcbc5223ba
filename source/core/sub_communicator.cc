// A communicator of some ranks of another, freed with its holder (core).

#include <deal.II/base/exceptions.h>

#include <softface/core/sub_communicator.h>

namespace softface
{
  SubCommunicator::SubCommunicator(const MPI_Comm parent, const bool member)
  {
    int       rank  = 0;
    const int error = MPI_Comm_rank(parent, &rank);
    AssertThrowMPI(error);
    const int split =
      MPI_Comm_split(parent, member ? 0 : MPI_UNDEFINED, rank, &communicator);
    AssertThrowMPI(split);
  }

  SubCommunicator::~SubCommunicator()
  {
    if (communicator != MPI_COMM_NULL)
      MPI_Comm_free(&communicator);
  }
} // namespace softface

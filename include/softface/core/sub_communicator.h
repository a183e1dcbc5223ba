#ifndef softface_core_sub_communicator_h
#define softface_core_sub_communicator_h

#include <deal.II/base/mpi.h>

namespace softface
{
  /**
   * The ranks of @p parent that pass @p member true, as a communicator of
   * their own (in @p parent's order); MPI_COMM_NULL on the others. Freed
   * however the scope that holds it ends. Collective on @p parent.
   */
  class SubCommunicator
  {
  public:
    SubCommunicator(const MPI_Comm parent, const bool member);
    ~SubCommunicator();
    SubCommunicator(const SubCommunicator &) = delete;
    SubCommunicator &
    operator=(const SubCommunicator &) = delete;

    MPI_Comm communicator = MPI_COMM_NULL;
  };
} // namespace softface

#endif

// Every rank reads the scene's mesh, run by ctest on 2 and 3
// ranks (mesh_read_on_ranks.mpirun=N.output): when one rank alone cannot read
// it (here: a rank given a file that does not exist, as a node that does not
// see the file would be), every rank throws the same error, that rank's
// message with its number, rather than one rank throwing while the others go
// on into a collective and wait. Also: every rank reading the file gets the
// same mesh, and rank 0's own failure is reported as it is; and where only
// some ranks read (the roots of groups), the failing one is named by its
// rank in MPI_COMM_WORLD.

#include <softface/core/error.h>
#include <softface/core/sub_communicator.h>
#include <softface/io/mesh_reader.h>

#include "tests.h"

using namespace softface;
using namespace softface_tests;

namespace
{
  // Every rank reads the shared gmsh cube, but rank @p rank_with_missing_file
  // (none if negative) a file that is not there: whether every rank failed,
  // with the same message.
  void
  check(const std::string &what, const int rank_with_missing_file)
  {
    const MPI_Comm     world = MPI_COMM_WORLD;
    const unsigned int rank  = Utilities::MPI::this_mpi_process(world);
    const std::string  mesh  = source_file("data/cube30k/mesh.msh");
    const std::string  file =
      int(rank) == rank_with_missing_file ? mesh + ".not-there" : mesh;
    Triangulation<3> triangulation;
    std::string      message;
    try
      {
        Mesh::read_file_on_every_rank(world, file, triangulation);
      }
    catch (const Error &e)
      {
        message = e.what();
      }
    const auto messages = Utilities::MPI::all_gather(world, message);
    bool       same     = true;
    for (const auto &m : messages)
      same &= m == messages[0];
    deallog << what << ':' << std::endl;
    if (rank_with_missing_file < 0)
      {
        check_equal("  ranks that failed",
                    Utilities::MPI::sum(int(!message.empty()), world),
                    0);
        const unsigned int cells = triangulation.n_active_cells();
        check_equal("  ranks whose mesh has rank 0's number of cells",
                    Utilities::MPI::sum(
                      int(cells == Utilities::MPI::broadcast(world, cells)),
                      world),
                    Utilities::MPI::n_mpi_processes(world));
        return;
      }
    check_equal("  ranks that failed",
                Utilities::MPI::sum(int(!message.empty()), world),
                Utilities::MPI::n_mpi_processes(world));
    check_equal("  every rank with the same message", same, 1);
    const std::string expected_start =
      rank_with_missing_file == 0 ?
        std::string("Cannot open mesh file") :
        "MPI rank " + std::to_string(rank_with_missing_file) +
          ": Cannot open mesh file";
    check_equal("  the message names the rank and the file's problem",
                messages[0].rfind(expected_start, 0) == 0 &&
                  messages[0].find(".not-there") != std::string::npos,
                1);
  }

  // Only the roots of groups of two ranks read (the even ranks, as when the
  // groups' members hold no cells), the last of them a file that is not
  // there: every reader fails with its message, which names the rank by its
  // number in MPI_COMM_WORLD, not among the readers.
  void
  check_readers_in_groups()
  {
    const MPI_Comm        world   = MPI_COMM_WORLD;
    const unsigned int    rank    = Utilities::MPI::this_mpi_process(world);
    const unsigned int    n_ranks = Utilities::MPI::n_mpi_processes(world);
    const unsigned int    last    = (n_ranks - 1) / 2 * 2;
    const std::string     mesh    = source_file("data/cube30k/mesh.msh");
    const SubCommunicator readers(world, rank % 2 == 0);
    std::string           message;
    if (readers.communicator != MPI_COMM_NULL)
      try
        {
          Triangulation<3> triangulation;
          Mesh::read_file_on_every_rank(readers.communicator,
                                        rank == last ? mesh + ".not-there" :
                                                       mesh,
                                        triangulation);
        }
      catch (const Error &e)
        {
          message = e.what();
        }
    deallog << "the roots of groups of two read, the last root cannot:"
            << std::endl;
    check_equal("  readers that failed",
                Utilities::MPI::sum(int(!message.empty()), world),
                (n_ranks + 1) / 2);
    const std::string expected =
      last == 0 ?
        std::string("Cannot open mesh file") :
        "MPI rank " + std::to_string(last) + ": Cannot open mesh file";
    check_equal("  readers whose message names the world rank",
                Utilities::MPI::sum(int(message.rfind(expected, 0) == 0),
                                    world),
                (n_ranks + 1) / 2);
  }
} // namespace

SOFTFACE_TEST(mesh_read_on_ranks)
{
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
  deallog << "ranks: " << n_ranks << std::endl;
  check("every rank reads the file", -1);
  check("the last rank cannot read it", n_ranks - 1);
  check("rank 0 cannot read it", 0);
  check_readers_in_groups();
}

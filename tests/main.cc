// The driver of all deal.II-style tests: softface_tests NAME runs the test
// registered as NAME with deallog writing to stdout. Under mpirun (tests named
// NAME.mpirun=N.output) only rank 0 writes, and a test failing on one rank
// ends every rank (MPI_Abort), so that none is left waiting in a collective.

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/process.h>
#include <softface/core/threads.h>

#include "tests.h"

#include <iostream>
#include <map>

namespace softface_tests
{
  std::map<std::string, void (*)()> &
  registry()
  {
    static std::map<std::string, void (*)()> tests;
    return tests;
  }

  bool
  register_test(const std::string &name, void (*function)())
  {
    registry()[name] = function;
    return true;
  }
} // namespace softface_tests

int
main(int argc, char **argv)
{
  softface::Process::prepare_serial_mpi();
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  softface::limit_blas_threads();
  const auto &tests = softface_tests::registry();
  if (argc != 2 || tests.count(argv[1]) == 0)
    {
      std::cerr << "usage: softface_tests NAME; tests:";
      for (const auto &test : tests)
        std::cerr << ' ' << test.first;
      std::cerr << std::endl;
      return 2;
    }
  const bool writer =
    dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  if (writer)
    dealii::deallog.attach(std::cout, /*print_job_id=*/false);
  dealii::deallog.depth_console(0);
  try
    {
      tests.at(argv[1])();
    }
  catch (const std::exception &e)
    {
      std::cout.flush();
      std::cerr << "test " << argv[1] << " failed";
      if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
        std::cerr << " on rank "
                  << dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
      std::cerr << ": " << softface::error_message(e) << std::endl;
      if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
        MPI_Abort(MPI_COMM_WORLD, 1);
      return 1;
    }
  return 0;
}

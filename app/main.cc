// softface: predict the soft tissue after maxillofacial surgery with several
// models side by side. Usage: softface scene.prm | --print-parameters | --help

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/mesh_source.h>
#include <softface/core/process.h>
#include <softface/core/threads.h>
#include <softface/effects/interface.h>
#include <softface/models/interface.h>
#include <softface/outputs/interface.h>
#include <softface/patient/commands.h>
#include <softface/serve/serve.h>
#include <softface/simulator/parameters.h>
#include <softface/simulator/simulator.h>

#include <chrono>
#include <iostream>
#include <string>
#include <thread>

int
main(int argc, char **argv)
{
  // Trilinos (the AMG solver) needs MPI initialised; softface runs serially,
  // without Open MPI's helper process.
  softface::Process::wall_time();
  softface::Process::prepare_serial_mpi();
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  softface::limit_blas_threads();

  const std::string usage =
    "usage: softface SCENE.prm            run a scene\n"
    "       softface phantom SCENE.prm    the patient stages of a patient "
    "scene, up to\n"
    "       softface segment SCENE.prm    the phantom CT, the segmentation and "
    "surfaces,\n"
    "       softface mesh SCENE.prm       or the bone parts and the "
    "tetrahedral mesh\n"
    "       softface postop SCENE.prm     a phantom's post-operative skull "
    "(parts moved by the Planning)\n"
    "       softface plan SCENE.prm       the Planning recovered from a "
    "post-operative skull by ICP\n"
    "       softface register SCENE.prm   a post-operative CT registered to "
    "the pre-operative one\n"
    "       softface preview SCENE.prm    pictures of the CT with labels, bone "
    "parts, cuts, seeds, region\n"
    "       softface serve SCENE.prm      a browser page to move the bones "
    "and see the face (Serve)\n"
    "       softface --print-parameters   print every parameter with its "
    "default and documentation\n"
    "       softface --help\n";
  try
    {
      if (argc == 3)
        {
          const std::string stage = argv[1];
          // The patient stages write their work folder, serve binds a
          // port: one process does them.
          if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
            throw softface::Error("softface " + stage +
                                  " runs on one MPI rank only; start it "
                                  "without mpirun.");
          if (stage == "serve")
            return softface::Serve::serve(argv[2], std::cout);
          if (stage != "phantom" && stage != "segment" && stage != "mesh" &&
              stage != "postop" && stage != "plan" && stage != "register" &&
              stage != "preview")
            {
              std::cerr << usage;
              return 2;
            }
          dealii::ParameterHandler prm;
          softface::Simulator::read_parameters(argv[2], prm);
          softface::OutputParameters output;
          output.parse_parameters(prm);
          return softface::Patient::run_command(
            prm, argv[2], stage, output.directory, std::cout);
        }
      if (argc != 2)
        {
          std::cerr << usage;
          return 2;
        }
      const std::string argument = argv[1];
      if (argument == "--help" || argument == "-h")
        {
          std::cout << usage << "\nmodels:\n"
                    << softface::Models::describe_registered() << "\neffects:\n"
                    << softface::Effects::describe_registered()
                    << "\nmesh sources:\n"
                    << softface::MeshSources::describe_registered()
                    << "\noutputs:\n"
                    << softface::Outputs::describe_registered();
          return 0;
        }
      if (argument == "--print-parameters")
        {
          softface::Simulator::print_default_parameters(std::cout);
          return 0;
        }
      softface::Simulator simulator;
      return simulator.run(argument);
    }
  catch (const std::exception &e)
    {
      // On several MPI ranks an error met by one rank alone would leave the
      // others waiting in a collective: the job is aborted. Rank 0 speaks
      // first; another rank speaks only if rank 0 did not end the job by
      // then (the error was its own), so that the message comes once.
      const unsigned int rank =
        dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
      const bool several =
        dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1;
      if (several && rank != 0)
        std::this_thread::sleep_for(std::chrono::seconds(5));
      std::cout.flush();
      // One write: mpirun forwards a rank's stderr as it reads it, and its
      // own banner about the abort may otherwise land inside the line.
      const std::string line =
        "softface: error: " + softface::error_message(e) + "\n";
      std::cerr << line << std::flush;
      if (several)
        {
          // Let mpirun read the line before it hears of the abort.
          std::this_thread::sleep_for(std::chrono::milliseconds(200));
          MPI_Abort(MPI_COMM_WORLD, 1);
        }
      return 1;
    }
}

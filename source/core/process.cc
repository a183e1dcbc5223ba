// Process start-up and whole-process wall time.

#include <softface/core/process.h>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace softface
{
  namespace Process
  {
    void
    prepare_serial_mpi()
    {
      // Variables that Open MPI's mpirun, PMIx or Slurm's srun set in the
      // processes they start.
      for (const char *launched :
           {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "SLURM_STEP_ID"})
        if (std::getenv(launched) != nullptr)
          return;
      setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite=*/0);
      const char *isolated = std::getenv("OMPI_MCA_ess_singleton_isolated");
      if (isolated == nullptr || std::string(isolated) != "1")
        return;

      // An isolated singleton always calls itself job 1, so every such
      // process on a host would share one session directory
      // (<tmp>/ompi.<host>.<uid>/jf.0/1): two processes starting and ending
      // at the same moment race on creating and removing it, and MPI_Init
      // then fails ("mkdir ... File exists"; 6 of 1500 runs of an empty MPI
      // program, 8 at a time). A directory of this process's own avoids it;
      // Open MPI removes it at MPI_Finalize.
      const char       *tmp = std::getenv("TMPDIR");
      const std::string session =
        std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") +
        "/softface-mpi." + std::to_string(getpid());
      setenv("OMPI_MCA_orte_top_session_dir", session.c_str(), /*overwrite=*/0);

      // A process alone talks only to itself. Choosing the point-to-point
      // layer and transport outright spares MPI_Init probing UCX and
      // libfabric for networks (`softface --help`: 0.66 s -> 0.38 s). A
      // user's choice in the environment stands; one in an Open MPI
      // parameter file does not (the environment wins over those).
      setenv("OMPI_MCA_pml", "ob1", /*overwrite=*/0);
      setenv("OMPI_MCA_btl", "self", /*overwrite=*/0);
    }

    namespace
    {
      // The process's start in seconds since boot, or a negative number.
      double
      start_since_boot()
      {
        std::ifstream stat("/proc/self/stat");
        std::string   line;
        if (!std::getline(stat, line))
          return -1;
        // The command name (field 2) may hold spaces: count fields after
        // its closing parenthesis; starttime is field 22.
        const auto close = line.rfind(')');
        if (close == std::string::npos || close + 1 >= line.size())
          return -1;
        std::istringstream fields(line.substr(close + 1));
        std::string        field;
        for (unsigned int f = 3; f < 22 && (fields >> field); ++f)
          {}
        unsigned long long ticks = 0;
        if (!(fields >> ticks))
          return -1;
        return static_cast<double>(ticks) / sysconf(_SC_CLK_TCK);
      }

      double
      uptime()
      {
        std::ifstream in("/proc/uptime");
        double        seconds = -1;
        if (!(in >> seconds))
          return -1;
        return seconds;
      }
    } // namespace

    double
    wall_time()
    {
      static const auto   first_call = std::chrono::steady_clock::now();
      static const double start      = start_since_boot();
      const double        now        = uptime();
      if (start >= 0 && now >= start)
        return now - start;
      return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                           first_call)
        .count();
    }
  } // namespace Process
} // namespace softface

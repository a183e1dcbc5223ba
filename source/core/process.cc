// Process start-up and whole-process wall time (issue 16).

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

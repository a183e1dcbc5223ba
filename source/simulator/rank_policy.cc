// What the MPI ranks of one run must agree on (simulator): failures, and the
// figures of a run taken from the slowest rank.

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/simulator/rank_policy.h>

#include <vector>

namespace softface
{
  namespace RankPolicy
  {
    void
    agree_on_failure(const bool failed, const std::string &what)
    {
      const MPI_Comm comm = MPI_COMM_WORLD;
      if (Utilities::MPI::n_mpi_processes(comm) > 1 &&
          Utilities::MPI::min(int(failed), comm) !=
            Utilities::MPI::max(int(failed), comm))
        throw Error(what +
                    (failed ? " failed on this rank and not on others" :
                              " failed on other ranks and not on this one") +
                    "; the ranks cannot go on together.");
    }

    bool
    is_every_ranks_failure(const std::exception &e)
    {
      return Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 1 ||
             dynamic_cast<const Error *>(&e) != nullptr;
    }

    void
    take_slowest_rank(Report::ModelRun &run)
    {
      const MPI_Comm      comm  = MPI_COMM_WORLD;
      auto               &s     = run.statistics;
      std::vector<double> local = {s.setup_time,
                                   s.solve_time,
                                   run.basis_time,
                                   run.peak_memory_mb};
      // Every rank ran the same phases (the ranks agree on failures); a
      // count that differs anyway keeps this rank's.
      const unsigned int n_phases    = s.phases.size();
      const bool         same_phases = Utilities::MPI::min(n_phases, comm) ==
                               Utilities::MPI::max(n_phases, comm);
      if (same_phases)
        for (const auto &[name, seconds] : s.phases)
          local.push_back(seconds);
      std::vector<double> largest(local.size());
      Utilities::MPI::max(local, comm, largest);
      s.setup_time       = largest[0];
      s.solve_time       = largest[1];
      run.basis_time     = largest[2];
      run.peak_memory_mb = largest[3];
      if (same_phases)
        for (unsigned int p = 0; p < n_phases; ++p)
          s.phases[p].second = largest[4 + p];
    }
  } // namespace RankPolicy
} // namespace softface

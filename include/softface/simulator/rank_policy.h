#ifndef softface_simulator_rank_policy_h
#define softface_simulator_rank_policy_h

#include <softface/outputs/report.h>

#include <exception>
#include <streambuf>
#include <string>

namespace softface
{
  /**
   * What the MPI ranks of one run must agree on. Every rank runs the same
   * scene and takes the same decisions; rank 0 speaks for all.
   */
  namespace RankPolicy
  {
    /// What the ranks other than 0 print goes nowhere, without failing the
    /// stream (deal.II's writers check it).
    class SilentBuffer : public std::streambuf
    {
    protected:
      int
      overflow(const int c) override
      {
        return traits_type::not_eof(c);
      }
    };

    /**
     * Ranks that disagree on whether @p what failed have left the same
     * path: the job cannot go on, and this throws (main() ends it).
     * Collective on MPI_COMM_WORLD; nothing on one rank.
     */
    void
    agree_on_failure(bool failed, const std::string &what);

    /**
     * Whether @p e may be a model's failure on every rank: on several ranks
     * only softface's own errors, which every rank meets alike (they hold
     * the same scene), are; anything else (memory, a library's exception)
     * may be one rank's, with the others waiting in a collective, and must
     * end the job. On one rank, every exception is the model's failure.
     */
    bool
    is_every_ranks_failure(const std::exception &e);

    /// On several ranks a run's times are the slowest rank's and its memory
    /// the largest rank's. Collective on MPI_COMM_WORLD.
    void
    take_slowest_rank(Report::ModelRun &run);
  } // namespace RankPolicy
} // namespace softface

#endif

#ifndef softface_models_stop_distance_check_h
#define softface_models_stop_distance_check_h

#include <cstddef>
#include <vector>

namespace softface
{
  /**
   * The check of a stop that a local stop criterion proposes (the mass
   * tensor model's 'Stop distance'): the criterion of Mollemans et al. 2007,
   * Sec. 2.3.3, can stop far from the answer where the sweeps converge slowly,
   * each sweep changing little long before the answer is near.
   *
   * The largest change of every sweep since the sweeps last (re)started
   * gives the rate rho at which the changes shrink, measured over the second
   * half of those sweeps: the slow error modes' rate creeps up over hundreds
   * of sweeps (106k off-centre cube: 0.913 per ten sweeps at sweep 50, 0.965
   * at 300, 0.973 at 1500), and a short window taken when the stop is
   * proposed (a few sweeps over every point) measured 0.59 and then 0.989
   * per sweep where the distance left asked for 0.997, so it promised 0.002
   * and then 0.09 mm where 0.40 mm were left. The distance left is about
   * the largest recent change times rho / (1 - rho).
   */
  class StopDistanceCheck
  {
  public:
    /// Accept stops within @p stop_distance (mm) of the answer, with the
    /// rate measured over windows of @p window sweeps; the threshold is
    /// never lowered below @p convergence_tolerance.
    StopDistanceCheck(const double       stop_distance,
                      const unsigned int window,
                      const double       convergence_tolerance);

    /// The largest change of the sweep just done (every sweep, in turn).
    void
    record(const double largest_change)
    {
      sweep_changes.push_back(largest_change);
    }

    /**
     * Is the stop proposed after the last sweep near enough the answer?
     * If not, every point sweeps on: with @p threshold lowered to what the
     * rate asks for, or, after too few sweeps to measure a rate, as it is
     * (each point's window is still below it, and the stop is proposed
     * again after a sweep). Where no rate can be trusted (the largest
     * change does not shrink, or the threshold cannot go lower) the stop is
     * accepted unchecked.
     */
    bool
    accept(double &threshold);

    unsigned int
    n_checks() const
    {
      return n_verifications;
    }
    /// Was a stop accepted without a rate to trust?
    bool
    unchecked() const
    {
      return unchecked_stop;
    }
    /// The last rate measured, and the distance left it estimated (mm).
    double
    rate() const
    {
      return contraction_rate;
    }
    double
    distance_left() const
    {
      return estimated_distance;
    }

  private:
    const double       stop_distance;
    const unsigned int W;
    const double       convergence_tolerance;
    /// After this many checks the stop is accepted unchecked.
    static constexpr unsigned int max_stop_checks = 100;

    std::vector<double> sweep_changes;
    std::size_t         restart            = 0;
    unsigned int        n_verifications    = 0;
    bool                unchecked_stop     = false;
    double              estimated_distance = 0.;
    double              contraction_rate   = 0.;
  };
} // namespace softface

#endif

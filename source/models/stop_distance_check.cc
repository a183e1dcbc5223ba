// The check of a proposed stop by the distance left to the answer (the mass
// tensor model's 'Stop distance'). See models/stop_distance_check.h.

#include <softface/models/stop_distance_check.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace softface
{
  StopDistanceCheck::StopDistanceCheck(const double       stop_distance,
                                       const unsigned int window,
                                       const double       convergence_tolerance)
      : stop_distance(stop_distance)
      , W(window)
      , convergence_tolerance(convergence_tolerance)
  {}

  bool
  StopDistanceCheck::accept(double &threshold)
  {
    ++n_verifications;
    const std::size_t k = sweep_changes.size();
    if (k - restart < 4 * W)
      return false;
    // The mean change of the first and the last W sweeps of the second half
    // of those since the restart; their ratio is rho to the power of their
    // distance.
    const std::size_t first = restart + (k - restart) / 2;
    double            early = 0., late = 0., latest = 0.;
    for (unsigned int i = 0; i < W; ++i)
      {
        early += sweep_changes[first + i] / W;
        late += sweep_changes[k - W + i] / W;
        latest = std::max(latest, sweep_changes[k - W + i]);
      }
    contraction_rate =
      early > 0. ? std::pow(late / early, 1. / (k - W - first)) : 0.;
    // Each further sweep would shrink the change by rho: the error left is
    // about change * rho / (1 - rho).
    estimated_distance = contraction_rate < 1. ?
                           latest * contraction_rate / (1. - contraction_rate) :
                           std::numeric_limits<double>::infinity();
    if (estimated_distance <= stop_distance)
      return true;
    // The largest change does not shrink (constraints switching, round-off
    // at a tiny threshold), or the threshold cannot go lower: no rate to
    // trust, the criterion of Mollemans et al. 2007 decides.
    if (contraction_rate >= 1. || threshold <= convergence_tolerance ||
        n_verifications > max_stop_checks)
      {
        unchecked_stop = true;
        return true;
      }
    threshold = std::max(convergence_tolerance,
                         std::min(0.5 * threshold,
                                  stop_distance * (1. - contraction_rate) /
                                    contraction_rate));
    restart   = k;
    return false;
  }
} // namespace softface

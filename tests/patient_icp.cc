// Planning from a post-operative skull (Mollemans et al. 2007, Sec. 3.2): ICP
// recovers a known rigid motion of a bone part. The part is the phantom's
// mandible (its surface from marching cubes of the truth labels at 2 mm
// voxels); the post-operative skull is the cranium's surface with the
// mandible's moved by a known motion (7 degrees about an oblique axis through
// the chin, and 4, -6, 3 mm). From starts 5 mm and 5 degrees off the truth, ICP
// gives the motion back to 0.05 mm (the largest error at any mandible point)
// and 0.05 degrees. And a start that leaves no pair within the rejection
// distance is refused with a message, not answered.

#include <softface/core/error.h>
#include <softface/patient/icp.h>
#include <softface/patient/phantom.h>
#include <softface/patient/surface.h>

#include "tests.h"

#include <cmath>

using namespace softface;
using namespace softface::Patient;

namespace
{
  std::vector<Vec3>
  surface_of(const LabelVolume &labels, const std::uint8_t label)
  {
    Volume<float> mask;
    mask.reinit_like(labels);
    for (std::size_t v = 0; v < labels.n_voxels(); ++v)
      mask.values[v] = (labels.values[v] == label);
    return iso_surface(mask, 0.5, true).points;
  }
} // namespace

SOFTFACE_TEST(patient_icp)
{
  PhantomParameters p;
  p.voxel_size = 2.;
  CTVolume    ct;
  LabelVolume truth;
  Phantom(p).acquire(ct, truth);
  const std::vector<Vec3> mandible = surface_of(truth, Phantom::mandible);
  const std::vector<Vec3> cranium  = surface_of(truth, Phantom::bone);
  softface_tests::print("mandible surface points", mandible.size(), 2);

  const RigidTransform motion = RigidTransform::from_planning(
    {{4., -6., 3.}}, {{1., 0.3, 0.2}}, 7., {{0., -60., -50.}});
  std::vector<Vec3> post_operative = cranium;
  for (const auto &x : mandible)
    post_operative.push_back(motion(x));

  // The error of a recovered motion: largest distance at the mandible's
  // points, and the angle of the rotation between the two.
  const auto errors = [&](const RigidTransform &t) {
    double largest = 0.;
    for (const auto &x : mandible)
      {
        const Vec3 a = t(x), b = motion(x);
        largest =
          std::max(largest, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
      }
    return std::make_pair(largest, t.after(motion.inverse()).angle_degrees());
  };

  unsigned int start = 0;
  for (const Vec3 axis : {Vec3{{0., 0., 1.}}, Vec3{{1., -1., 0.5}}})
    {
      // Off by 5 degrees about the axis and 5 mm across it.
      const RigidTransform off = RigidTransform::from_planning(
        {{0., 0., 0.}}, axis, 5., {{0., -40., -40.}});
      RigidTransform shift;
      shift.translation            = {{3., 4., 0.}};
      const RigidTransform initial = shift.after(off.after(motion));
      const auto [d0, a0]          = errors(initial);
      const std::string name       = "start " + std::to_string(++start);
      softface_tests::print(name + ": start error (mm)", d0, 2);
      softface_tests::print(name + ": start error (degrees)", a0, 2);

      const IcpResult result =
        icp(mandible, post_operative, initial, IcpParameters());
      const auto [d, a] = errors(result.transform);
      softface_tests::check_below(name + ": error (mm)", d, 0.05);
      softface_tests::check_below(name + ": error (degrees)", a, 0.05);
      softface_tests::check_equal(name + ": converged", result.converged, 1);
    }

  // Too far off: no pair within the rejection distance.
  RigidTransform far;
  far.translation = {{500., 0., 0.}};
  try
    {
      icp(mandible, post_operative, far, IcpParameters());
      dealii::deallog << "a start 500 mm off: answered (wrong)" << std::endl;
    }
  catch (const Error &e)
    {
      dealii::deallog << "a start 500 mm off: " << e.what() << std::endl;
    }
}

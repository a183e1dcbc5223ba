// Segmentation thresholds chosen from the scan's histogram ('auto', patient;
// Mollemans et al. 2007, Sec. 3.1). On the phantom (1.5 mm voxels, no metal
// streaks) the chosen thresholds segment every tissue as the fixed defaults do,
// to 1 % of its volume (the bone is printed against the phantom's truth too).
// The same CT in other units (value * 2 + 1024 and value * 0.5 - 300: a
// scanner's stored values are a scale and an offset away from HU), and the CT
// in HU with a scanner's padding outside the reconstructed circle, get the same
// labels but for a few voxels, and thresholds that are those of the CT in
// HU once mapped back. Thresholds that ignored the scan (the defaults in
// HU, say) would miss the body and the bone of the rescaled CTs: most
// labels would differ.

#include <softface/patient/phantom.h>
#include <softface/patient/segmentation.h>

#include "tests.h"

#include <cmath>
#include <tuple>

using namespace softface;
using namespace softface::Patient;

namespace
{
  // Voxels of each label (0 outside the body ... 5 internal soft tissue).
  std::vector<double>
  label_counts(const LabelVolume &labels)
  {
    std::vector<double> counts(6, 0.);
    for (const auto l : labels.values)
      if (l < counts.size())
        counts[l] += 1.;
    return counts;
  }
} // namespace

SOFTFACE_TEST(patient_auto_thresholds)
{
  PhantomParameters p;
  p.voxel_size    = 1.5;
  p.metal_streaks = false;
  CTVolume    ct;
  LabelVolume truth;
  Phantom(p).acquire(ct, truth);

  const SegmentationParameters fixed;
  SegmentationParameters       automatic;
  automatic.auto_body_threshold       = true;
  automatic.auto_bone_threshold       = true;
  automatic.auto_fat_threshold        = true;
  const SegmentationResult by_default = segment(ct, fixed, "phantom");
  const SegmentationResult by_auto    = segment(ct, automatic, "phantom");

  dealii::deallog << "phantom in HU: "
                  << describe_thresholds(automatic, by_auto) << std::endl;
  const std::vector<double> n_fixed = label_counts(by_default.labels),
                            n_auto  = label_counts(by_auto.labels);
  const char *names[6] = {"", "skin", "fat", "muscle", "bone", "internal"};
  for (unsigned int l = 1; l < 6; ++l)
    {
      const double cm3 = ct.voxel_volume() / 1000.;
      softface_tests::print(std::string(names[l]) + ": fixed thresholds (cm^3)",
                            n_fixed[l] * cm3,
                            5);
      softface_tests::print(std::string(names[l]) + ": auto thresholds (cm^3)",
                            n_auto[l] * cm3,
                            5);
      softface_tests::check_below(std::string(names[l]) +
                                    ": |auto - fixed| / fixed",
                                  std::abs(n_auto[l] - n_fixed[l]) / n_fixed[l],
                                  0.01,
                                  2);
    }

  // The bone against the phantom's truth.
  double n_truth_bone = 0.;
  for (const auto t : truth.values)
    n_truth_bone +=
      t == Phantom::bone || t == Phantom::mandible || t == Phantom::teeth;
  softface_tests::print("bone: truth (cm^3)",
                        n_truth_bone * ct.voxel_volume() / 1000.,
                        5);
  softface_tests::print("bone: (fixed - truth) / truth",
                        (n_fixed[bone_tissue] - n_truth_bone) / n_truth_bone,
                        2);
  softface_tests::print("bone: (auto - truth) / truth",
                        (n_auto[bone_tissue] - n_truth_bone) / n_truth_bone,
                        2);

  // The CT in other units: HU = (value - offset) / scale.
  std::size_t n_body = 0;
  for (const auto l : by_auto.labels.values)
    n_body += l != outside_body;
  // The last: in HU, with a scanner's padding (-3024) outside the circle
  // each axial slice is reconstructed in.
  for (const auto &[scale, offset, padded] :
       {std::tuple<double, double, bool>{2., 1024., false},
        {0.5, -300., false},
        {1., 0., true}})
    {
      CTVolume rescaled = ct;
      for (auto &v : rescaled.values)
        v = static_cast<std::int16_t>(std::lround(scale * v + offset));
      if (padded)
        for (std::size_t k = 0; k < ct.size[2]; ++k)
          for (std::size_t j = 0; j < ct.size[1]; ++j)
            for (std::size_t i = 0; i < ct.size[0]; ++i)
              if (std::hypot((i + 0.5) / ct.size[0] - 0.5,
                             (j + 0.5) / ct.size[1] - 0.5) > 0.5)
                rescaled(i, j, k) = -3024;
      const SegmentationResult r = segment(rescaled, automatic, "rescaled");
      const std::string        units =
        padded ? std::string("padded outside the circle") :
                        "value * " + softface_tests::rounded(scale) +
                   (offset < 0. ? " - " : " + ") +
                   softface_tests::rounded(std::abs(offset), 4);
      dealii::deallog << units << ": " << describe_thresholds(automatic, r)
                      << std::endl;
      const auto hu = [&](const double t) { return (t - offset) / scale; };
      softface_tests::print(units + ": body threshold in HU",
                            hu(r.body_threshold),
                            4);
      softface_tests::print(units + ": bone threshold in HU",
                            hu(r.bone_threshold),
                            4);
      softface_tests::print(units + ": fat threshold in HU",
                            hu(r.fat_threshold),
                            4);
      std::size_t differing = 0;
      for (std::size_t v = 0; v < r.labels.n_voxels(); ++v)
        differing += r.labels.values[v] != by_auto.labels.values[v];
      dealii::deallog << units
                      << ": voxels labelled otherwise than in HU: " << differing
                      << " of " << n_body << " in the body" << std::endl;
      softface_tests::check_below(units + ": their fraction of the body",
                                  differing / double(n_body),
                                  1e-3,
                                  2);
    }
}

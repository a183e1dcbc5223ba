// An osteotomy at two voxel sizes (Mollemans et al. 2007, Sec. 3.2): a bone bar
// along y, 10 x 100 x 10 mm, cut by a frontal plane at y = 0.2 mm with a 1.5 mm
// kerf.
//
// With a box that holds the bar's whole cross-section, the bar splits into
// a front and a back part at 1 mm and at 0.5 mm voxels alike; their volumes
// differ between the voxel sizes by at most one layer of voxels, where the
// kerf's voxels are handed to the parts.
//
// With a box that ends 3 mm short of the bar's top, the bone above it
// joins the parts: the error names the cut and where the bone passes its
// surface beyond the box, at either voxel size.

#include <softface/core/error.h>
#include <softface/patient/osteotomy.h>

#include "tests.h"

using namespace softface;
using namespace softface::Patient;
using namespace dealii;

namespace
{
  const std::uint8_t bone = 4;

  // The bar in a volume with a 5 mm margin on each side.
  LabelVolume
  bar(const double h)
  {
    LabelVolume labels;
    const auto  n = [&](const double length) {
      return std::size_t(std::lround(length / h));
    };
    labels.size    = {{n(20.), n(110.), n(20.)}};
    labels.origin  = {{-10. + 0.5 * h, -55. + 0.5 * h, -10. + 0.5 * h}};
    labels.spacing = {{h, h, h}};
    labels.values.assign(labels.n_voxels(), 0);
    for (std::size_t k = 0; k < labels.size[2]; ++k)
      for (std::size_t j = 0; j < labels.size[1]; ++j)
        for (std::size_t i = 0; i < labels.size[0]; ++i)
          {
            const Vec3 x = labels.point(i, j, k);
            if (std::abs(x[0]) < 5. && std::abs(x[1]) < 50. &&
                std::abs(x[2]) < 5.)
              labels(i, j, k) = bone;
          }
    return labels;
  }

  OsteotomyParameters
  frontal_cut(const double box_top)
  {
    OsteotomyParameters osteotomy;
    osteotomy.kerf            = 1.5;
    osteotomy.detached_margin = 0.;
    osteotomy.min_part_volume = 10.;
    Cut cut;
    cut.name            = "frontal";
    cut.point           = {{0., 0.2, 0.}};
    cut.normal          = {{0., 1., 0.}};
    cut.box_min         = {{-20., -10., -20.}};
    cut.box_max         = {{20., 10., box_top}};
    cut.detached_margin = 0.;
    osteotomy.cuts      = {cut};
    return osteotomy;
  }

  const std::vector<SegmentSeed> segments = {{"front", {{0., -40., 0.}}},
                                             {"back", {{0., 40., 0.}}}};
} // namespace

SOFTFACE_TEST(osteotomy_bridge)
{
  for (const double h : {1., 0.5})
    {
      const LabelVolume labels = bar(h);
      const LabelVolume parts =
        split_bone(labels, bone, frontal_cut(20.), segments);
      std::array<double, 3> volume = {{0., 0., 0.}};
      for (const std::uint8_t p : parts.values)
        if (p > 0 && p <= 2)
          volume[p] += labels.voxel_volume();
      deallog << "voxels of " << h << " mm, the box holds the bar: front "
              << volume[1] << " mm^3, back " << volume[2] << " mm^3"
              << std::endl;
    }
  for (const double h : {1., 0.5})
    try
      {
        split_bone(bar(h), bone, frontal_cut(2.), segments);
        throw std::runtime_error("a bar joined above the box was split");
      }
    catch (const Error &e)
      {
        deallog << "voxels of " << h
                << " mm, the box ends at z = 2 mm:" << std::endl
                << e.what() << std::endl;
      }
}

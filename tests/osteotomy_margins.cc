// The detached margins of an osteotomy (Mollemans et al. 2007, Sec. 3.2; the
// setbacks' splits): a bone bar along y cut by two frontal planes, one with the
// osteotomy's margin (3 mm) and one with a margin of its own (8 mm, as a
// setback's sagittal splits get). Bone within a cut's margin, and only there,
// is detached: per cut, the detached voxels lie within its margin and fill the
// bar's cross-section over the margin's width on each side (kerf included).
// Parsed, a cut without a margin of its own takes the osteotomy's; a margin
// out of range is refused with the parameter's name.

#include <deal.II/base/parameter_handler.h>

#include <softface/core/error.h>
#include <softface/patient/osteotomy.h>

#include "tests.h"

#include <cmath>

using namespace softface;
using namespace softface::Patient;
using namespace dealii;

SOFTFACE_TEST(osteotomy_margins)
{
  // 1 mm voxels; the bar is 10 x 100 x 10 voxels, centred at the origin.
  LabelVolume labels;
  labels.size    = {{20, 120, 20}};
  labels.origin  = {{-9.5, -59.5, -9.5}};
  labels.spacing = {{1., 1., 1.}};
  labels.values.assign(labels.n_voxels(), 0);
  const std::uint8_t bone = 4;
  for (std::size_t k = 5; k < 15; ++k)
    for (std::size_t j = 10; j < 110; ++j)
      for (std::size_t i = 5; i < 15; ++i)
        labels(i, j, k) = bone;

  OsteotomyParameters osteotomy;
  osteotomy.kerf            = 1.5;
  osteotomy.detached_margin = 3.;
  Cut front;
  front.name              = "front";
  front.point             = {{0., -20., 0.}};
  front.normal            = {{0., 1., 0.}};
  front.detached_margin   = osteotomy.detached_margin;
  Cut back                = front;
  back.name               = "back";
  back.point              = {{0., 20., 0.}};
  back.detached_margin    = 8.;
  osteotomy.cuts          = {front, back};
  const LabelVolume parts = split_bone(labels,
                                       bone,
                                       osteotomy,
                                       {{"front part", {{0., -40., 0.}}},
                                        {"middle part", {{0., 0., 0.}}},
                                        {"back part", {{0., 40., 0.}}}});

  for (const Cut &cut : osteotomy.cuts)
    {
      std::size_t detached = 0, outside = 0, inside_kept = 0;
      for (std::size_t k = 0; k < labels.size[2]; ++k)
        for (std::size_t j = 0; j < labels.size[1]; ++j)
          for (std::size_t i = 0; i < labels.size[0]; ++i)
            {
              if (labels(i, j, k) != bone)
                continue;
              const double d =
                std::abs(labels.point(i, j, k)[1] - cut.point[1]);
              if (d > 15.)
                continue; // the other cut's
              const bool lifted = is_detached(parts(i, j, k));
              detached += lifted;
              outside += lifted && d >= cut.detached_margin;
              inside_kept += !lifted && d < cut.detached_margin;
            }
      deallog << "cut '" << cut.name << "', margin " << cut.detached_margin
              << " mm:" << std::endl;
      softface_tests::check_equal("  detached voxels beyond the margin",
                                  outside,
                                  0);
      softface_tests::check_equal("  bone voxels within the margin kept",
                                  inside_kept,
                                  0);
      // Voxel centres at 0.5, 1.5, ... mm from the plane, on both sides.
      const double rows = 2. * std::round(cut.detached_margin);
      softface_tests::check_equal("  detached voxels / bar cross-section",
                                  detached / 100,
                                  std::llround(rows));
    }

  // The parameters: a cut without a margin of its own takes the
  // osteotomy's, one with its own keeps it; a margin out of range names
  // itself.
  const auto parse = [](const std::string &right, const std::string &left) {
    ParameterHandler prm;
    prm.enter_subsection("Scene");
    prm.enter_subsection("Patient");
    OsteotomyParameters::declare_parameters(prm, {"bsso right", "bsso left"});
    prm.leave_subsection();
    prm.leave_subsection();
    prm.parse_input_from_string(
      "subsection Scene\n subsection Patient\n  subsection Osteotomy\n"
      "   set Cuts = bsso right, bsso left\n"
      "   set Detached margin = 5\n"
      "   subsection Cut bsso right\n    set Detached margin = " +
      right +
      "\n   end\n   subsection Cut bsso left\n"
      "    set Detached margin = " +
      left + "\n   end\n  end\n end\nend\n");
    prm.enter_subsection("Scene");
    prm.enter_subsection("Patient");
    OsteotomyParameters parsed;
    parsed.parse_parameters(prm);
    return parsed;
  };
  const OsteotomyParameters parsed = parse("", "8");
  deallog << "osteotomy margin 5, 'bsso right' none of its own, 'bsso left' "
             "8:"
          << std::endl;
  softface_tests::check_equal("  'bsso right' (mm)",
                              parsed.cuts[0].detached_margin,
                              5);
  softface_tests::check_equal("  'bsso left' (mm)",
                              parsed.cuts[1].detached_margin,
                              8);
  try
    {
      parse("80", "");
      throw std::runtime_error("a margin of 80 mm was accepted");
    }
  catch (const Error &e)
    {
      deallog << e.what() << std::endl;
    }
}

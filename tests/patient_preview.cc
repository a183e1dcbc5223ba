// 'softface preview' draws a seed point and a cut where they are. The
// preview of a small phantom scene (2 mm voxels) through the mandible's
// seed point is read back from its PNG files; the pixels of the seed
// marker's colour and of the cut's colour inside each slice's image are
// mapped back to mm by the layout slice_picture.h documents (the image at
// (80, 60), the CT's largest extent over 600 pixels; axial: x right, y
// down; coronal: x right, z up; sagittal: y right, z up), written out here
// on its own, not through the code that drew them. The centre of the
// marker's pixels and the line fitted through the cut's pixels are printed
// beside the scene's seed point and the cut plane's trace on the slice: a
// drawing shifted, mirrored or on the wrong axis prints other numbers.

#include <softface/patient/image_io.h>
#include <softface/patient/preview.h>
#include <softface/patient/preview_colours.h>

#include "tests.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <tuple>

using namespace softface;
using namespace softface::Patient;

namespace
{
  std::string
  mm(const double x)
  {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << (std::abs(x) < 0.05 ? 0. : x);
    return s.str();
  }

  // The picture's layout, as documented: pixel (px, py) of the image of a
  // slice to the two in-plane coordinates (mm) of its axes.
  struct Layout
  {
    double       lower[3], upper[3], pixels_per_mm;
    unsigned int h_axis, v_axis;
    bool         v_up;
    std::array<double, 2>
    operator()(const double px, const double py) const
    {
      const double h = lower[h_axis] + (px + 0.5 - 80.) / pixels_per_mm;
      const double v = v_up ? upper[v_axis] - (py + 0.5 - 60.) / pixels_per_mm :
                              lower[v_axis] + (py + 0.5 - 60.) / pixels_per_mm;
      return {{h, v}};
    }
  };

  // The pixels of colour @p c in the slice's image, in mm.
  std::vector<std::array<double, 2>>
  pixels_of(const RgbImage &image, const Colour &c, const Layout &layout)
  {
    std::vector<std::array<double, 2>> points;
    const double                       w =
      (layout.upper[layout.h_axis] - layout.lower[layout.h_axis]) *
      layout.pixels_per_mm;
    const double h =
      (layout.upper[layout.v_axis] - layout.lower[layout.v_axis]) *
      layout.pixels_per_mm;
    for (long y = 60; y < 60 + long(h); ++y)
      for (long x = 80; x < 80 + long(w); ++x)
        {
          const std::size_t p = 3 * (std::size_t(y) * image.width + x);
          if (image.rgb[p] == c[0] && image.rgb[p + 1] == c[1] &&
              image.rgb[p + 2] == c[2])
            points.push_back(layout(x, y));
        }
    return points;
  }

  // Centre and direction (angle from the h axis towards the v axis, in
  // degrees, in (-90, 90]) of the line through @p points.
  std::array<double, 3>
  fit_line(const std::vector<std::array<double, 2>> &points)
  {
    double ch = 0., cv = 0.;
    for (const auto &p : points)
      ch += p[0], cv += p[1];
    ch /= points.size(), cv /= points.size();
    double shh = 0., svv = 0., shv = 0.;
    for (const auto &p : points)
      {
        shh += (p[0] - ch) * (p[0] - ch);
        svv += (p[1] - cv) * (p[1] - cv);
        shv += (p[0] - ch) * (p[1] - cv);
      }
    double angle = 0.5 * std::atan2(2. * shv, shh - svv) * 180. / M_PI;
    if (angle <= -90.)
      angle += 180.;
    return {{ch, cv, angle}};
  }
} // namespace

SOFTFACE_TEST(patient_preview)
{
  PatientParameters prm;
  prm.work_directory     = "patient_preview_work";
  prm.phantom.voxel_size = 2.;
  std::filesystem::remove_all(prm.work_directory);
  const std::vector<SegmentSeed> segments = {{"cranium", {{0., -40., 30.}}},
                                             {"mandible",
                                              {{-15., -58., -42.}}}};
  // A plane slanted in y and z: on the sagittal slice a line at -36.87
  // degrees, on the axial and coronal ones lines across x.
  Cut cut;
  cut.name                = "slanted";
  cut.point               = {{-15., -70., -30.}};
  cut.normal              = {{0., 0.6, 0.8}};
  cut.box_min             = {{-40., -110., -70.}};
  cut.box_max             = {{10., -45., 0.}};
  prm.osteotomy.cuts      = {cut};
  prm.preview_point_given = true;
  prm.preview_point       = segments[1].point;

  std::ostringstream out;
  const int          code = preview(prm, segments, out);
  dealii::deallog << "exit code " << code << std::endl;
  std::istringstream lines(out.str());
  for (std::string line; std::getline(lines, line);)
    for (const std::string start :
         {"  point", "  seed point", "  cut", "  bone parts"})
      if (line.rfind(start, 0) == 0)
        dealii::deallog << line.substr(2) << std::endl;

  // The CT's extent (the phantom's frame has no rotation).
  const CTVolume ct = read_ct(prm.work_directory + "/ct.nii.gz");
  softface_tests::check_equal(
    "CT without rotation",
    ct.direction == std::array<double, 9>{{1, 0, 0, 0, 1, 0, 0, 0, 1}},
    1);
  Layout layout;
  double largest = 0.;
  for (unsigned int d = 0; d < 3; ++d)
    {
      layout.lower[d] = ct.origin[d] - 0.5 * ct.spacing[d];
      layout.upper[d] = ct.origin[d] + (ct.size[d] - 0.5) * ct.spacing[d];
      largest         = std::max(largest, layout.upper[d] - layout.lower[d]);
    }
  layout.pixels_per_mm = 600. / largest;

  const char *axis_name[3] = {"x", "y", "z"};
  const Vec3 &seed         = segments[1].point;
  for (const auto &[view, h, v, up] : {std::tuple{"axial", 0u, 1u, false},
                                       std::tuple{"coronal", 0u, 2u, true},
                                       std::tuple{"sagittal", 1u, 2u, true}})
    {
      layout.h_axis = h, layout.v_axis = v, layout.v_up = up;
      const RgbImage image =
        read_png(prm.work_directory + "/preview/" + view + ".png");
      const std::string axes =
        std::string("(") + axis_name[h] + ", " + axis_name[v] + ")";

      const auto marker = pixels_of(image, PreviewColours::seed, layout);
      double     ch = 0., cv = 0.;
      for (const auto &p : marker)
        ch += p[0] / marker.size(), cv += p[1] / marker.size();
      dealii::deallog << view << ": seed marker " << axes << " = (" << mm(ch)
                      << ", " << mm(cv) << ") mm, the scene's seed point ("
                      << mm(seed[h]) << ", " << mm(seed[v]) << ")" << std::endl;

      // The plane's trace on the slice: n_h h + n_v v = c.
      const auto line = fit_line(pixels_of(image, PreviewColours::cut, layout));
      const Vec3        &n = cut.normal;
      const unsigned int w = 3 - h - v;
      const double       c = n[h] * cut.point[h] + n[v] * cut.point[v] +
                       n[w] * (cut.point[w] - seed[w]);
      double scene_angle = std::atan2(-n[h], n[v]) * 180. / M_PI;
      if (scene_angle <= -90.)
        scene_angle += 180.;
      if (scene_angle > 90.)
        scene_angle -= 180.;
      dealii::deallog << view << ": cut line through " << axes << " = ("
                      << mm(line[0]) << ", " << mm(line[1]) << ") mm at "
                      << mm(line[2])
                      << " degrees; the plane's trace: " << axis_name[v]
                      << " = " << mm((c - n[h] * line[0]) / n[v])
                      << " mm there, at " << mm(scene_angle) << " degrees"
                      << std::endl;
    }
}

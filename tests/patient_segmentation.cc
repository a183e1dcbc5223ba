// The patient pipeline's first stages against the phantom's truth
// (Mollemans et al. 2007, Sec. 3.1): a phantom head acquired as a noisy,
// blurred CT at 1.5 mm voxels, written as NIfTI and read back through ITK (the
// frame must survive), then segmented. The segmented volumes of the body, the
// bone, the facial soft tissue and the internal soft tissue equal the phantom's
// truth labels to 1%; the dense skin surface from marching cubes lies within
// half a voxel of the phantom's analytic skin (the zero level of its implicit
// function, reached by Newton steps along the gradient), and its skull surface
// is closed.

#include <softface/patient/image_io.h>
#include <softface/patient/phantom.h>
#include <softface/patient/segmentation.h>
#include <softface/patient/surface.h>

#include "tests.h"

#include <algorithm>
#include <cmath>
#include <map>

using namespace softface;
using namespace softface::Patient;

SOFTFACE_TEST(patient_segmentation)
{
  PhantomParameters p;
  p.voxel_size    = 1.5;
  p.metal_streaks = false;
  const Phantom phantom(p);
  CTVolume      acquired;
  LabelVolume   truth;
  phantom.acquire(acquired, truth);

  // Through the file format: the frame (origin, spacing, direction) and the
  // values come back as they went.
  write_volume(acquired, "patient_segmentation_ct.nii.gz");
  const CTVolume ct          = read_ct("patient_segmentation_ct.nii.gz");
  double         frame_error = 0.;
  for (const auto &ijk : {Vec3{{0., 0., 0.}}, Vec3{{10., 20., 30.}}})
    {
      const Vec3 a = acquired.point(ijk[0], ijk[1], ijk[2]),
                 b = ct.point(ijk[0], ijk[1], ijk[2]);
      for (unsigned int d = 0; d < 3; ++d)
        frame_error = std::max(frame_error, std::abs(a[d] - b[d]));
    }
  softface_tests::check_below("NIfTI round trip: voxel position error (mm)",
                              frame_error,
                              1e-4);
  softface_tests::check_equal("NIfTI round trip: equal voxels",
                              ct.values == acquired.values,
                              1);

  SegmentationParameters s;
  const auto             result = segment(ct, s, "phantom");
  const auto            &labels = result.labels;

  // Truth and segmentation counted in the same classes.
  enum Class
  {
    body,
    bone,
    facial_soft_tissue,
    internal_soft_tissue,
    n_classes
  };
  std::vector<double> v_truth(n_classes, 0.), v_segmented(n_classes, 0.);
  for (std::size_t v = 0; v < truth.n_voxels(); ++v)
    {
      const auto t = truth.values[v];
      if (t != Phantom::air)
        v_truth[body] += 1;
      if (t == Phantom::bone || t == Phantom::mandible || t == Phantom::teeth)
        v_truth[bone] += 1;
      if (t == Phantom::skin || t == Phantom::fat || t == Phantom::muscle)
        v_truth[facial_soft_tissue] += 1;
      if (t == Phantom::brain)
        v_truth[internal_soft_tissue] += 1;

      const auto l = labels.values[v];
      if (l != outside_body)
        v_segmented[body] += 1;
      if (l == bone_tissue)
        v_segmented[bone] += 1;
      if (l == skin_tissue || l == fat_tissue || l == muscle_tissue)
        v_segmented[facial_soft_tissue] += 1;
      if (l == internal_tissue)
        v_segmented[internal_soft_tissue] += 1;
    }
  const char *names[n_classes] = {"body",
                                  "bone",
                                  "facial soft tissue",
                                  "internal soft tissue"};
  for (unsigned int c = 0; c < n_classes; ++c)
    {
      softface_tests::print(std::string(names[c]) + ": truth (cm^3)",
                            v_truth[c] * ct.voxel_volume() / 1000.,
                            3);
      softface_tests::check_below(std::string(names[c]) +
                                    ": |segmented - truth| / truth",
                                  std::abs(v_segmented[c] - v_truth[c]) /
                                    v_truth[c],
                                  0.01);
    }

  // The skin surface against the analytic skin.
  const TriangleSurface skin = iso_surface(result.smoothed,
                                           s.body_threshold,
                                           /*largest_piece=*/true);
  // The distance of a point to the analytic skin: Newton steps along the
  // gradient of the implicit function onto its zero level.
  const auto distance_to_skin = [&](const Vec3 &x0) {
    Vec3 x = x0;
    for (unsigned int it = 0; it < 40; ++it)
      {
        const double f = phantom.skin_function(x);
        Vec3         g;
        double       g2 = 0.;
        for (unsigned int d = 0; d < 3; ++d)
          {
            Vec3 a = x, b = x;
            a[d] += 1e-3;
            b[d] -= 1e-3;
            g[d] = (phantom.skin_function(a) - phantom.skin_function(b)) / 2e-3;
            g2 += g[d] * g[d];
          }
        if (std::abs(f) < 1e-6 || g2 == 0.)
          break;
        // Steps of at most 0.2 mm: the function is only about a distance.
        const double step = std::min(1., 0.2 / (std::abs(f) / std::sqrt(g2)));
        for (unsigned int d = 0; d < 3; ++d)
          x[d] -= step * f * g[d] / g2;
      }
    return std::hypot(x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]);
  };
  double largest = 0., sum = 0.;
  for (const auto &x : skin.points)
    {
      const double d = distance_to_skin(x);
      largest        = std::max(largest, d);
      sum += d;
    }
  softface_tests::check_above("skin vertices", skin.points.size(), 20000);
  softface_tests::check_below("skin: mean distance to the analytic skin / "
                              "voxel",
                              sum / skin.points.size() / p.voxel_size,
                              0.25);
  softface_tests::check_below("skin: largest distance to the analytic skin / "
                              "voxel",
                              largest / p.voxel_size,
                              0.5);

  // A closed surface where the volume does not cut it (the field of view
  // cuts the cranium's top): every edge away from the volume's border is
  // shared by exactly two triangles.
  const TriangleSurface skull =
    iso_surface(result.smoothed, s.bone_threshold, false, 200);
  Vec3 low = ct.point(0, 0, 0), high = low;
  for (const double i : {0., ct.size[0] - 1.})
    for (const double j : {0., ct.size[1] - 1.})
      for (const double k : {0., ct.size[2] - 1.})
        {
          const Vec3 corner = ct.point(i, j, k);
          for (unsigned int d = 0; d < 3; ++d)
            {
              low[d]  = std::min(low[d], corner[d]);
              high[d] = std::max(high[d], corner[d]);
            }
        }
  const auto inside = [&](const Vec3 &x) {
    for (unsigned int d = 0; d < 3; ++d)
      if (x[d] < low[d] + p.voxel_size || x[d] > high[d] - p.voxel_size)
        return false;
    return true;
  };
  std::map<std::pair<unsigned int, unsigned int>, unsigned int> edges;
  for (const auto &t : skull.triangles)
    for (unsigned int e = 0; e < 3; ++e)
      ++edges[std::minmax(t[e], t[(e + 1) % 3])];
  unsigned int open = 0;
  for (const auto &[edge, count] : edges)
    open += count != 2 && inside(skull.points[edge.first]) &&
            inside(skull.points[edge.second]);
  softface_tests::check_equal(
    "skull: edges inside the volume not shared by two triangles", open, 0);
}

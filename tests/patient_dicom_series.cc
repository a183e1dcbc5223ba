// The phantom's CT as a DICOM series, as a scanner's export holds one, read
// back through ITK and GDCM (the CT input of Mollemans et al. 2007, Sec. 3.1).
// tests/dicom_series.py writes a volume as a series of int16 slices whose
// stored values become Hounsfield units only through the rescale (slope 0.5,
// intercept -1024), files and instance numbers counting down where the slice
// positions go up along the normal, and beside it, in the same folder, a scout
// the reader must leave out: a lateral image of another SeriesInstanceUID and a
// frontal one with the scan's (as some scanners write it) but its own
// series number, both of another size and orientation.
//
// 1. The phantom at 2 mm written as NIfTI and read back is the reference.
//    Written as a DICOM series, it reads back as the same volume: the same
//    size (the scout left out), every voxel the same number of Hounsfield
//    units (the rescale applied), every voxel at the same point in space
//    (the slices stacked by their positions, not by their names or numbers).
//    So the labels are the same voxel for voxel and the skin surface the
//    same point for point (the mesh, made from the labels alone, is then
//    the same too: not made again).
// 2. The same head scanned on an oblique grid (turned 10 degrees about the
//    left-right axis through the grid's centre: a head lying turned in the
//    scanner, or an oblique reconstruction), written as
//    NIfTI and as a DICOM series: both read back alike (voxels and frame).
//    The reference lies on another grid, so only what lies in space is
//    compared with it: the labels at the same points, the tissue volumes
//    and the skin surface's centroid and extent in the region both grids
//    cover, the mesh's volume. A direction ignored by the reader leaves
//    fewer than half of the body's voxels labelled as the reference's
//    there and moves the skin's centroid by 14 mm.

#include <softface/patient/image_io.h>
#include <softface/patient/phantom.h>
#include <softface/patient/segmentation.h>
#include <softface/patient/surface.h>
#include <softface/patient/tetrahedral_mesh.h>

#include "phantom_le_fort.h"
#include "tests.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

using namespace softface;
using namespace softface::Patient;
using dealii::deallog;

namespace
{
  /// tests/dicom_series.py: the NIfTI volume @p nifti as a DICOM series in
  /// the folder @p folder.
  void
  write_dicom_series(const std::string &nifti, const std::string &folder)
  {
    const std::string command = "/usr/bin/python3 " +
                                softface_tests::source_file("dicom_series.py") +
                                " " + nifti + " " + folder;
    if (std::system(command.c_str()) != 0)
      throw std::runtime_error(command + " failed");
  }

  /// The largest distance between the positions two volumes of the same
  /// size give a voxel (at the corners of the grid: the maps are affine).
  double
  position_difference(const CTVolume &a, const CTVolume &b)
  {
    double largest = 0.;
    for (const double i : {0., a.size[0] - 1.})
      for (const double j : {0., a.size[1] - 1.})
        for (const double k : {0., a.size[2] - 1.})
          {
            const Vec3 x = a.point(i, j, k), y = b.point(i, j, k);
            largest =
              std::max(largest,
                       std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]));
          }
    return largest;
  }

  template <typename T>
  std::size_t
  n_different(const Volume<T> &a, const Volume<T> &b)
  {
    std::size_t n = 0;
    for (std::size_t v = 0; v < a.n_voxels(); ++v)
      n += a.values[v] != b.values[v];
    return n;
  }

  /// "the first and the second volume have the same size" (the test ends
  /// here otherwise: nothing else compares voxel for voxel).
  void
  check_same_size(const std::string &what, const CTVolume &a, const CTVolume &b)
  {
    deallog << what << ": " << b.size[0] << " x " << b.size[1] << " x "
            << b.size[2] << " voxels" << std::endl;
    if (a.size != b.size)
      throw std::runtime_error(what + ": not the size of the NIfTI volume");
  }

  /// Whether @p x lies among the voxel centres of @p volume, at least
  /// @p margin voxels inside.
  template <typename T>
  bool
  inside(const Volume<T> &volume, const Vec3 &x, const double margin)
  {
    const Vec3 c = volume.continuous_index(x);
    for (unsigned int d = 0; d < 3; ++d)
      if (!(c[d] >= margin && c[d] <= volume.size[d] - 1. - margin))
        return false;
    return true;
  }

  /// The part of a surface whose triangles' centroids lie in a region:
  /// its area, area-weighted centroid and bounding box.
  struct SurfacePart
  {
    double area = 0.;
    Vec3   centroid{{0., 0., 0.}};
    Vec3   low{{1e30, 1e30, 1e30}}, high{{-1e30, -1e30, -1e30}};
  };

  template <typename Region>
  SurfacePart
  surface_part(const TriangleSurface &surface, const Region &region)
  {
    SurfacePart part;
    for (const auto &t : surface.triangles)
      {
        const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]],
                   &c = surface.points[t[2]];
        Vec3 centre, u, v;
        for (unsigned int d = 0; d < 3; ++d)
          {
            centre[d] = (a[d] + b[d] + c[d]) / 3.;
            u[d]      = b[d] - a[d];
            v[d]      = c[d] - a[d];
          }
        if (!region(centre))
          continue;
        const double area = 0.5 * std::hypot(u[1] * v[2] - u[2] * v[1],
                                             u[2] * v[0] - u[0] * v[2],
                                             u[0] * v[1] - u[1] * v[0]);
        part.area += area;
        for (unsigned int d = 0; d < 3; ++d)
          {
            part.centroid[d] += area * centre[d];
            for (const Vec3 *p : {&a, &b, &c})
              {
                part.low[d]  = std::min(part.low[d], (*p)[d]);
                part.high[d] = std::max(part.high[d], (*p)[d]);
              }
          }
      }
    for (unsigned int d = 0; d < 3; ++d)
      part.centroid[d] /= part.area;
    return part;
  }
} // namespace

SOFTFACE_TEST(patient_dicom_series)
{
  PhantomParameters p;
  p.voxel_size = 2.;
  const Phantom phantom(p);
  CTVolume      acquired;
  LabelVolume   truth;
  phantom.acquire(acquired, truth);
  write_volume(acquired, "patient_dicom_series.nii.gz");
  const CTVolume reference = read_ct("patient_dicom_series.nii.gz");

  const SegmentationParameters s;
  const auto                   le_fort = softface_tests::phantom_le_fort();
  const auto reference_labels = segment(reference, s, "the NIfTI volume");
  const TriangleSurface reference_skin =
    iso_surface(reference_labels.smoothed, s.body_threshold, true);
  const TetrahedralMesh reference_mesh = le_fort.mesh(reference_labels.labels);
  deallog << "NIfTI: " << reference.size[0] << " x " << reference.size[1]
          << " x " << reference.size[2] << " voxels, skin surface of "
          << reference_skin.points.size() << " points" << std::endl;

  // 1. The same volume as a DICOM series.
  {
    write_dicom_series("patient_dicom_series.nii.gz",
                       "patient_dicom_series_axial");
    const CTVolume ct = read_ct("patient_dicom_series_axial");
    check_same_size("axial DICOM", reference, ct);
    softface_tests::check_below("axial DICOM: largest voxel position "
                                "difference to the NIfTI's (mm)",
                                position_difference(reference, ct),
                                1e-3,
                                1);
    softface_tests::check_equal("axial DICOM: voxels whose HU differ from the "
                                "NIfTI's",
                                n_different(reference, ct),
                                0);
    const auto labels = segment(ct, s, "the DICOM series");
    softface_tests::check_equal("axial DICOM: voxels labelled differently",
                                n_different(reference_labels.labels,
                                            labels.labels),
                                0);
    const TriangleSurface skin =
      iso_surface(labels.smoothed, s.body_threshold, true);
    softface_tests::check_equal("axial DICOM: skin surface points - the "
                                "NIfTI's",
                                static_cast<long long>(skin.points.size()) -
                                  static_cast<long long>(
                                    reference_skin.points.size()),
                                0);
    double largest = 0.;
    for (std::size_t n = 0; n < skin.points.size(); ++n)
      for (unsigned int d = 0; d < 3; ++d)
        largest =
          std::max(largest,
                   std::abs(skin.points[n][d] - reference_skin.points[n][d]));
    softface_tests::check_below("axial DICOM: largest skin point difference "
                                "(mm)",
                                largest,
                                1e-4,
                                1);
  }

  // 2. The same head on an oblique grid: turned 10 degrees about the x axis
  // through the centre of the phantom's grid.
  CTVolume     grid   = phantom.grid();
  const double angle  = 10. * M_PI / 180.;
  const Vec3   centre = grid.point(0.5 * (grid.size[0] - 1.),
                                 0.5 * (grid.size[1] - 1.),
                                 0.5 * (grid.size[2] - 1.));
  grid.direction      = {{1.,
                          0.,
                          0.,
                          0.,
                          std::cos(angle),
                          -std::sin(angle),
                          0.,
                          std::sin(angle),
                          std::cos(angle)}};
  grid.origin         = centre;
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int c = 0; c < 3; ++c)
      grid.origin[r] -=
        grid.direction[3 * r + c] * grid.spacing[c] * 0.5 * (grid.size[c] - 1.);
  CTVolume    oblique_acquired;
  LabelVolume oblique_truth;
  phantom.acquire(grid, oblique_acquired, oblique_truth);
  write_volume(oblique_acquired, "patient_dicom_series_oblique.nii.gz");
  const CTVolume oblique_nifti = read_ct("patient_dicom_series_oblique.nii.gz");
  write_dicom_series("patient_dicom_series_oblique.nii.gz",
                     "patient_dicom_series_oblique");
  const CTVolume ct = read_ct("patient_dicom_series_oblique");
  check_same_size("oblique DICOM", oblique_nifti, ct);
  softface_tests::check_below("oblique DICOM: largest voxel position "
                              "difference to the oblique NIfTI's (mm)",
                              position_difference(oblique_nifti, ct),
                              1e-3,
                              1);
  softface_tests::check_below("oblique DICOM: largest voxel position "
                              "difference to the grid acquired (mm)",
                              position_difference(oblique_acquired, ct),
                              1e-3,
                              1);
  softface_tests::check_equal("oblique DICOM: voxels whose HU differ from "
                              "the oblique NIfTI's",
                              n_different(oblique_nifti, ct),
                              0);

  // Against the reference, in the region both grids cover.
  const auto labels  = segment(ct, s, "the oblique DICOM series");
  const auto in_both = [&](const Vec3 &x, const double margin) {
    return inside(reference, x, margin) && inside(ct, x, margin);
  };
  std::size_t n_body = 0, n_same = 0;
  for (std::size_t k = 0; k < ct.size[2]; ++k)
    for (std::size_t j = 0; j < ct.size[1]; ++j)
      for (std::size_t i = 0; i < ct.size[0]; ++i)
        {
          std::array<std::size_t, 3> ijk;
          if (!reference.nearest_voxel(ct.point(i, j, k), ijk))
            continue;
          const auto a = labels.labels(i, j, k),
                     b = reference_labels.labels(ijk[0], ijk[1], ijk[2]);
          if (a == outside_body && b == outside_body)
            continue;
          ++n_body;
          n_same += a == b;
        }
  softface_tests::check_within("oblique DICOM: body voxels labelled as the "
                               "reference's nearest voxel (fraction)",
                               double(n_same) / n_body,
                               0.9,
                               1.);
  const std::pair<SegmentLabel, const char *> tissues[] = {
    {skin_tissue, "skin"},
    {fat_tissue, "fat"},
    {muscle_tissue, "muscle"},
    {bone_tissue, "bone"},
    {internal_tissue, "internal"}};
  for (const auto &[tissue, name] : tissues)
    {
      // Each volume's voxels whose centres the other grid covers.
      double v_reference = 0., v_oblique = 0.;
      for (std::size_t v = 0; v < reference.n_voxels(); ++v)
        if (reference_labels.labels.values[v] == tissue &&
            inside(ct,
                   reference.point(v % reference.size[0],
                                   v / reference.size[0] % reference.size[1],
                                   v / reference.size[0] / reference.size[1]),
                   0.))
          v_reference += reference.voxel_volume();
      for (std::size_t v = 0; v < ct.n_voxels(); ++v)
        if (labels.labels.values[v] == tissue &&
            inside(reference,
                   ct.point(v % ct.size[0],
                            v / ct.size[0] % ct.size[1],
                            v / ct.size[0] / ct.size[1]),
                   0.))
          v_oblique += ct.voxel_volume();
      softface_tests::print(std::string("reference: ") + name +
                              " in the common region (cm^3)",
                            v_reference / 1000.);
      softface_tests::check_within(std::string("oblique DICOM: ") + name +
                                     " volume / the reference's",
                                   v_oblique / v_reference,
                                   0.97,
                                   1.03);
    }

  // The skin surface where both grids cover it (two voxels in from their
  // borders, where the surface is cut open).
  const TriangleSurface skin =
    iso_surface(labels.smoothed, s.body_threshold, true);
  const auto        region = [&](const Vec3 &x) { return in_both(x, 2.); };
  const SurfacePart a      = surface_part(reference_skin, region),
                    b      = surface_part(skin, region);
  softface_tests::print("reference: skin area in the common region (cm^2)",
                        a.area / 100.);
  softface_tests::check_within("oblique DICOM: skin area / the reference's",
                               b.area / a.area,
                               0.98,
                               1.02);
  for (unsigned int d = 0; d < 3; ++d)
    {
      const std::string axis(1, "xyz"[d]);
      softface_tests::print("reference: skin centroid " + axis + " (mm)",
                            a.centroid[d]);
      softface_tests::check_within("oblique DICOM: skin centroid " + axis +
                                     " - the reference's (mm)",
                                   b.centroid[d] - a.centroid[d],
                                   -0.5,
                                   0.5,
                                   2);
      deallog << "reference: skin extent in " << axis
              << " (mm): " << softface_tests::rounded(a.low[d]) << " to "
              << softface_tests::rounded(a.high[d]) << std::endl;
      softface_tests::check_within("oblique DICOM: skin extent in " + axis +
                                     " - the reference's, low (mm)",
                                   b.low[d] - a.low[d],
                                   -2.,
                                   2.,
                                   2);
      softface_tests::check_within("oblique DICOM: skin extent in " + axis +
                                     " - the reference's, high (mm)",
                                   b.high[d] - a.high[d],
                                   -2.,
                                   2.,
                                   2);
    }

  // The mesh of the soft tissue in the region of interest (which both grids
  // cover): from labels on another grid, Mesh_3 makes another mesh, so its
  // volume is compared and its number of cells bounded.
  const TetrahedralMesh mesh             = le_fort.mesh(labels.labels);
  const double          reference_volume = reference_mesh.quality().volume;
  softface_tests::print("reference: mesh volume (cm^3)",
                        reference_volume / 1000.);
  softface_tests::check_within("oblique DICOM: mesh volume / the reference's",
                               mesh.quality().volume / reference_volume,
                               0.97,
                               1.03);
  softface_tests::check_within("oblique DICOM: tetrahedra / the reference's",
                               double(mesh.cells.size()) /
                                 reference_mesh.cells.size(),
                               0.8,
                               1.25,
                               2);
}

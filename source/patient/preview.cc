// 'softface preview' (preview.h): the patient stages up to the bone parts,
// then pictures of what the scene says about the CT (labels, parts, cuts,
// seed points, region of interest) and a listing of where each seed point
// and cut lies, for a user who checks a new CT's scene before a run.

#include <softface/core/error.h>
#include <softface/patient/bone_view.h>
#include <softface/patient/image_io.h>
#include <softface/patient/png_io.h>
#include <softface/patient/preview.h>
#include <softface/patient/slice_picture.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      namespace fs = std::filesystem;

      std::string
      point_text(const Vec3 &x)
      {
        std::ostringstream s;
        s << std::setprecision(4) << "(" << x[0] << ", " << x[1] << ", " << x[2]
          << ")";
        return s.str();
      }

      // The slices' point: the user's, else the centre of the region of
      // interest's box within the CT (the default box is unbounded), else
      // the CT's centre.
      Vec3
      preview_point(const PatientParameters &prm,
                    const VolumeBounds      &bounds,
                    std::string             &why)
      {
        Vec3 x;
        if (prm.preview_point_given)
          {
            why = "Scene/Patient/Preview/Point";
            return prm.preview_point;
          }
        bool in_ct = true;
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double lo = std::max(prm.roi.box_min[d], bounds.lower[d]);
            const double hi = std::min(prm.roi.box_max[d], bounds.upper[d]);
            in_ct &= lo < hi;
            x[d] = 0.5 * (lo + hi);
          }
        if (in_ct)
          {
            why = "the centre of the region of interest within the CT";
            return x;
          }
        for (unsigned int d = 0; d < 3; ++d)
          x[d] = 0.5 * (bounds.lower[d] + bounds.upper[d]);
        why = "the centre of the CT";
        return x;
      }

      // Where a seed point lies: outside the CT, in bone, or how far from
      // the nearest bone (the osteotomy looks 5 mm around it).
      std::string
      seed_place(const LabelVolume &labels, const Vec3 &seed)
      {
        std::array<std::size_t, 3> ijk;
        if (!labels.nearest_voxel(seed, ijk))
          return "outside the CT";
        if (labels(ijk[0], ijk[1], ijk[2]) == bone_tissue)
          return "in the CT, in bone";
        double     best = std::numeric_limits<double>::infinity();
        const Vec3 c    = labels.continuous_index(seed);
        const long r    = 10;
        for (long k = -r; k <= r; ++k)
          for (long j = -r; j <= r; ++j)
            for (long i = -r; i <= r; ++i)
              {
                const long a = std::lround(c[0]) + i, b = std::lround(c[1]) + j,
                           e = std::lround(c[2]) + k;
                if (a < 0 || b < 0 || e < 0 || a >= long(labels.size[0]) ||
                    b >= long(labels.size[1]) || e >= long(labels.size[2]) ||
                    labels(a, b, e) != bone_tissue)
                  continue;
                const Vec3 x = labels.point(a, b, e);
                best         = std::min(best,
                                std::hypot(x[0] - seed[0],
                                           x[1] - seed[1],
                                           x[2] - seed[2]));
              }
        std::ostringstream s;
        s << "in the CT, not in bone (";
        if (std::isfinite(best))
          s << "nearest bone " << std::setprecision(2) << best << " mm)";
        else
          s << "no bone within " << r << " voxels)";
        return s.str();
      }

      // Where a cut lies: the voxels within half a kerf of its surface and
      // inside its box (those it removes), and the bone among them.
      std::string
      cut_place(const LabelVolume         &labels,
                const Cut                 &cut,
                const OsteotomyParameters &prm)
      {
        const double half_kerf =
          0.5 * std::max(prm.kerf,
                         1.01 * std::max({labels.spacing[0],
                                          labels.spacing[1],
                                          labels.spacing[2]}));
        std::size_t n = 0, n_bone = 0;
        for (std::size_t k = 0; k < labels.size[2]; ++k)
          for (std::size_t j = 0; j < labels.size[1]; ++j)
            for (std::size_t i = 0; i < labels.size[0]; ++i)
              {
                const Vec3 x = labels.point(i, j, k);
                if (!cut.in_box(x) || cut.surface_distance(x) >= half_kerf)
                  continue;
                ++n;
                n_bone += labels(i, j, k) == bone_tissue;
              }
        if (n == 0)
          return "outside the CT (no voxel within half a kerf of it in its "
                 "box)";
        std::ostringstream s;
        s << "in the CT, its kerf through " << std::setprecision(3)
          << n_bone * labels.voxel_volume() / 1000. << " cm^3 of bone";
        return s.str();
      }

      // The bone parts, or why they could not be made (the message
      // without its pointer to the preview, which is running).
      bool
      make_parts(const LabelVolume              &labels,
                 const PatientParameters        &prm,
                 const std::vector<SegmentSeed> &segments,
                 LabelVolume                    &parts,
                 std::string                    &failure)
      {
        try
          {
            parts = split_bone(labels, bone_tissue, prm.osteotomy, segments);
            return true;
          }
        catch (const Error &e)
          {
            failure                = e.what();
            const std::string hint = preview_hint(prm.osteotomy.scene_file);
            if (failure.size() >= hint.size() &&
                failure.compare(failure.size() - hint.size(),
                                hint.size(),
                                hint) == 0)
              failure.erase(failure.size() - hint.size());
            // The bone alone, for the 3D views.
            parts.reinit_like(labels);
            for (std::size_t v = 0; v < labels.n_voxels(); ++v)
              parts.values[v] = labels.values[v] == bone_tissue;
            return false;
          }
      }

      // The listing: where each seed point and cut lies, and the parts.
      void
      list_scene(const PatientParameters        &prm,
                 const std::vector<SegmentSeed> &segments,
                 const LabelVolume              &labels,
                 const LabelVolume              *parts,
                 const std::string              &failure,
                 std::ostream                   &out)
      {
        for (const auto &seed : segments)
          out << "  seed point of '" << seed.name << "' "
              << point_text(seed.point) << ": "
              << seed_place(labels, seed.point) << '\n';
        for (const auto &cut : prm.osteotomy.cuts)
          out << "  cut '" << cut.name << "' (" << cut.type
              << "): " << cut_place(labels, cut, prm.osteotomy) << '\n';
        if (parts != nullptr)
          {
            std::vector<std::size_t> count(segments.size() + 1, 0);
            // Detached bone (near a cut) counts with its part.
            for (const auto p : parts->values)
              if (part_number(p) >= 1 && part_number(p) <= segments.size())
                ++count[part_number(p)];
            out << "  bone parts:";
            for (unsigned int s = 0; s < segments.size(); ++s)
              out << (s ? ", " : " ") << segments[s].name << ' '
                  << std::setprecision(3)
                  << count[s + 1] * parts->voxel_volume() / 1000. << " cm^3";
            out << '\n';
          }
        else
          out << "  bone parts: not made: " << failure << '\n';
      }
    } // namespace

    int
    preview(const PatientParameters        &prm,
            const std::vector<SegmentSeed> &segments,
            std::ostream                   &out)
    {
      const auto start = std::chrono::steady_clock::now();
      build_patient_model(prm, segments, Stage::segmentation, out);
      const fs::path work(prm.work_directory);
      CTVolume       ct;
      try
        {
          ct = read_ct(prm.ct_volume.empty() ? (work / "ct.nii.gz").string() :
                                               prm.ct_volume);
        }
      catch (const Error &e)
        {
          throw Error(std::string("Scene/Patient/CT volume: ") + e.what());
        }
      const LabelVolume labels = read_labels((work / "labels.nii.gz").string());
      LabelVolume       parts;
      std::string       failure;
      const bool split = make_parts(labels, prm, segments, parts, failure);

      const VolumeBounds bounds = VolumeBounds::of(ct);
      std::string        why;
      const Vec3         point = preview_point(prm, bounds, why);
      out << "  point " << point_text(point) << " mm: " << why
          << (bounds.contains(point) ? "" : " (outside the CT)") << '\n';
      list_scene(prm, segments, labels, split ? &parts : nullptr, failure, out);

      const fs::path folder = work / "preview";
      fs::create_directories(folder);
      const SliceContent content{
        ct, labels, split ? &parts : nullptr, segments, prm.osteotomy, prm.roi};
      std::vector<std::string> files;
      const auto save = [&](const RgbImage &image, const std::string &name) {
        write_png(image, (folder / name).string());
        files.push_back(name);
      };
      save(slice_picture(content, {SliceGeometry::axial, bounds, point}),
           "axial.png");
      save(slice_picture(content, {SliceGeometry::coronal, bounds, point}),
           "coronal.png");
      save(slice_picture(content, {SliceGeometry::sagittal, bounds, point}),
           "sagittal.png");
      const std::vector<SegmentSeed> none;
      const TriangleSurface          surface = bone_surface(parts);
      for (const auto side : {BoneViewSide::front, BoneViewSide::left})
        save(bone_view(parts, surface, split ? segments : none, side),
             side == BoneViewSide::front ? "bone_parts_front.png" :
                                           "bone_parts_left.png");
      out << "Files in " << folder.string() << "/:";
      for (const auto &f : files)
        out << ' ' << f;
      out << " (wall time " << std::fixed << std::setprecision(1)
          << std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                           start)
               .count()
          << " s)" << std::defaultfloat << std::endl;
      return split ? 0 : 1;
    }
  } // namespace Patient
} // namespace softface

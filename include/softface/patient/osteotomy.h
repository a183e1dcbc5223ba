#ifndef softface_patient_osteotomy_h
#define softface_patient_osteotomy_h

#include <deal.II/base/parameter_handler.h>

#include <softface/patient/volume.h>

#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * A cut surface of an osteotomy (Mollemans et al. 2007, Sec. 3.2), named as
     * in the clinic (Le Fort I, bilateral sagittal split left and right,
     * genioplasty): a plane (a point and its normal) or a polyline swept along
     * a direction, each bounded by a box so that it cuts only the bone it is
     * meant for.
     */
    struct Cut
    {
      std::string       name;
      std::string       type = "plane"; ///< "plane" or "swept polyline"
      Vec3              point{{0., 0., 0.}};
      Vec3              normal{{0., 0., 1.}};
      std::vector<Vec3> polyline;
      Vec3              sweep{{1., 0., 0.}};
      Vec3              box_min{{-1e9, -1e9, -1e9}};
      Vec3              box_max{{1e9, 1e9, 1e9}};
      /// mm: bone this close to the cut holds no soft tissue (its own
      /// 'Detached margin', or else the osteotomy's).
      double detached_margin = 3.;

      /// Distance of @p x to the cut surface (mm); infinite outside its box.
      double
      distance(const Vec3 &x) const;

      /// Distance of @p x to the cut surface extended beyond its box (mm).
      double
      surface_distance(const Vec3 &x) const;

      /// Is @p x inside the cut's box?
      bool
      in_box(const Vec3 &x) const;
    };

    struct OsteotomyParameters
    {
      /// Subsection "Osteotomy": the list of cuts, one "Cut <name>" each.
      static void
      declare_parameters(dealii::ParameterHandler       &prm,
                         const std::vector<std::string> &cut_names);
      static std::vector<std::string>
      cut_names(dealii::ParameterHandler &prm);
      void
      parse_parameters(dealii::ParameterHandler &prm);

      std::vector<Cut> cuts;
      double           kerf = 1.5; ///< mm, width of a saw cut
      /// mm: bone this close to a cut holds no soft tissue (detached_flag),
      /// for the cuts that do not set their own.
      double detached_margin = 3.;
      double min_part_volume = 500.; ///< mm^3
      /// The scene file the cuts come from, for preview_hint(); empty:
      /// unknown.
      std::string scene_file;
    };

    /**
     * What ends each error about seed points, cuts and bone parts: the
     * command that draws them (softface preview) on @p scene_file, or on
     * "SCENE.prm" when it is not known.
     */
    std::string
    preview_hint(const std::string &scene_file);

    /**
     * Added by split_bone() to the value of bone within the detached margin
     * of a cut: the soft tissue touching it is free, and the bone stays its
     * segment's (for registration and pictures).
     */
    constexpr std::uint8_t detached_flag = 128;

    /// The segment number + 1 of a value of split_bone()'s volume (0: none).
    constexpr unsigned int
    part_number(const std::uint8_t value)
    {
      return value & (detached_flag - 1);
    }

    /// Whether a value of split_bone()'s volume is detached bone.
    constexpr bool
    is_detached(const std::uint8_t value)
    {
      return (value & detached_flag) != 0;
    }

    /// A bone segment as the osteotomy needs it: a name and a point in it.
    struct SegmentSeed
    {
      std::string name;
      Vec3        point;
    };

    /**
     * The bone parts (paper, Sec. 3.2-3.3): the bone of @p labels (value
     * @p bone_label) minus the saw kerfs of the cuts, split into connected
     * pieces; the piece that holds a segment's seed point (or the nearest
     * bone within 5 mm of it) is that segment's. Returns a volume with s + 1
     * on every bone voxel of segment s; kerf voxels and pieces smaller than
     * 'Minimum part volume' go to the nearest part through the bone.
     * Bone within a cut's detached margin (at least one voxel beyond the
     * kerf) then gets detached_flag added: the soft tissue touching it is
     * free. At most 127 segments.
     * Throws an Error when a seed point is not in bone, when two segments fall
     * in one piece (a cut does not separate them), or when a piece larger than
     * the minimum volume belongs to no segment.
     */
    LabelVolume
    split_bone(const LabelVolume              &labels,
               const std::uint8_t              bone_label,
               const OsteotomyParameters      &parameters,
               const std::vector<SegmentSeed> &segments);
  } // namespace Patient
} // namespace softface

#endif

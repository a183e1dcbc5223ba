// Osteotomies (patient; Mollemans et al. 2007, Sec. 3.2-3.3): named cut
// surfaces split the segmented skull into bone parts, and each part becomes the
// bone segment whose seed point lies in it; the join points of the soft-tissue
// mesh then follow from the part each bone-contact face touches.

#include <softface/core/error.h>
#include <softface/patient/osteotomy.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      double
      dot(const Vec3 &a, const Vec3 &b)
      {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      }

      Vec3
      sub(const Vec3 &a, const Vec3 &b)
      {
        return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
      }

      // Distance from x to the parallelogram a + s u + t v, s, t in [0, 1].
      double
      parallelogram_distance(const Vec3 &x,
                             const Vec3 &a,
                             const Vec3 &u,
                             const Vec3 &v)
      {
        // Closest point in the plane, clamped by a few projections.
        const Vec3   d  = sub(x, a);
        const double uu = dot(u, u), vv = dot(v, v), uv = dot(u, v);
        const double du = dot(d, u), dv = dot(d, v);
        const double det = uu * vv - uv * uv;
        double s = (du * vv - dv * uv) / det, t = (dv * uu - du * uv) / det;
        s = std::clamp(s, 0., 1.);
        t = std::clamp((dv - s * uv) / vv, 0., 1.);
        s = std::clamp((du - t * uv) / uu, 0., 1.);
        Vec3 q;
        for (unsigned int c = 0; c < 3; ++c)
          q[c] = a[c] + s * u[c] + t * v[c];
        const Vec3 r = sub(x, q);
        return std::sqrt(dot(r, r));
      }
    } // namespace

    std::string
    preview_hint(const std::string &scene_file)
    {
      return " Run 'softface preview " +
             (scene_file.empty() ? std::string("SCENE.prm") : scene_file) +
             "' to see the seed points, cuts and bone parts.";
    }

    bool
    Cut::in_box(const Vec3 &x) const
    {
      for (unsigned int d = 0; d < 3; ++d)
        if (x[d] < box_min[d] || x[d] > box_max[d])
          return false;
      return true;
    }

    double
    Cut::distance(const Vec3 &x) const
    {
      return in_box(x) ? surface_distance(x) :
                         std::numeric_limits<double>::infinity();
    }

    double
    Cut::surface_distance(const Vec3 &x) const
    {
      if (type == "plane")
        return std::abs(dot(sub(x, point), normal));
      // A polyline swept along the sweep direction, as far as the box goes:
      // parallelograms between consecutive polyline points.
      double       best  = std::numeric_limits<double>::infinity();
      const double reach = 1e3;
      for (std::size_t i = 0; i + 1 < polyline.size(); ++i)
        {
          Vec3 a = polyline[i], u = sub(polyline[i + 1], polyline[i]), v;
          for (unsigned int c = 0; c < 3; ++c)
            {
              a[c] -= reach * sweep[c];
              v[c] = 2. * reach * sweep[c];
            }
          best = std::min(best, parallelogram_distance(x, a, u, v));
        }
      return best;
    }

    namespace
    {
      /// Per voxel: 0 no bone, 1 bone outside the kerfs, 2 bone in a kerf;
      /// and whether the voxel lies within a cut's detached margin.
      struct BoneState
      {
        std::vector<std::uint8_t> state;
        std::vector<bool>         detached;
      };

      // The connected pieces (face neighbours) of the uncut bone.
      struct Pieces
      {
        std::vector<int>         piece; ///< per voxel; -1: none
        std::vector<std::size_t> size;  ///< voxels per piece
        std::vector<std::size_t> example;
      };

      // Visit the face neighbours of voxel @p v.
      template <typename Visit>
      void
      for_neighbours(const LabelVolume &labels,
                     const std::size_t  v,
                     const Visit       &visit)
      {
        const auto &size      = labels.size;
        const long  stride[3] = {1, long(size[0]), long(size[0] * size[1])};
        std::size_t c[3]      = {v % size[0],
                                 (v / size[0]) % size[1],
                                 v / (size[0] * size[1])};
        for (unsigned int d = 0; d < 3; ++d)
          {
            if (c[d] > 0)
              visit(v - stride[d]);
            if (c[d] + 1 < size[d])
              visit(v + stride[d]);
          }
      }

      // A kerf narrower than a voxel may fall between two layers of voxel
      // centres and separate nothing: it is at least one voxel wide.
      double
      voxel_kerf(const LabelVolume &labels, const OsteotomyParameters &prm)
      {
        return std::max(prm.kerf,
                        1.01 * std::max({labels.spacing[0],
                                         labels.spacing[1],
                                         labels.spacing[2]}));
      }

      // A detached margin that ends inside the kerf's neighbouring voxel
      // layer detaches nothing at coarse voxels (3 mm at 2 mm voxels: the
      // layer next to the kerf has its centre 3 mm from the cut), and the
      // tissue in the kerf stays pinned to both parts: a nonzero margin
      // reaches at least one voxel beyond the kerf.
      double
      voxel_detached_margin(const LabelVolume &labels,
                            const double       kerf,
                            const double       margin)
      {
        if (margin <= 0.)
          return 0.;
        return std::max(margin,
                        0.5 * kerf + 1.01 * std::max({labels.spacing[0],
                                                      labels.spacing[1],
                                                      labels.spacing[2]}));
      }

      BoneState
      mark_kerfs(const LabelVolume         &labels,
                 const std::uint8_t         bone_label,
                 const OsteotomyParameters &prm)
      {
        const std::size_t   n    = labels.n_voxels();
        const auto         &size = labels.size;
        const double        kerf = voxel_kerf(labels, prm);
        std::vector<double> margins;
        for (const Cut &cut : prm.cuts)
          margins.push_back(
            voxel_detached_margin(labels, kerf, cut.detached_margin));
        // Bone outside the kerfs: what the cuts leave connected.
        BoneState bone;
        auto     &state    = bone.state;
        auto     &detached = bone.detached;
        state.assign(n, 0);
        detached.assign(n, false);
        for (std::size_t k = 0; k < size[2]; ++k)
          for (std::size_t j = 0; j < size[1]; ++j)
            for (std::size_t i = 0; i < size[0]; ++i)
              {
                const std::size_t v = labels.index(i, j, k);
                if (labels.values[v] != bone_label)
                  continue;
                state[v]     = 1;
                const Vec3 x = labels.point(i, j, k);
                for (const Cut &cut : prm.cuts)
                  {
                    const double d = cut.distance(x);
                    if (d < 0.5 * kerf)
                      state[v] = 2;
                    if (d < margins[&cut - prm.cuts.data()])
                      detached[v] = true;
                  }
              }

        return bone;
      }

      Pieces
      connected_pieces(const LabelVolume               &labels,
                       const std::vector<std::uint8_t> &state)
      {
        const std::size_t n = labels.n_voxels();
        Pieces            pieces;
        auto             &piece         = pieces.piece;
        auto             &piece_size    = pieces.size;
        auto             &piece_example = pieces.example;
        piece.assign(n, -1);
        std::deque<std::size_t> queue;
        // Connected pieces (face neighbours) of the uncut bone.
        for (std::size_t v = 0; v < n; ++v)
          if (state[v] == 1 && piece[v] < 0)
            {
              const int p = piece_size.size();
              piece_size.push_back(0);
              piece_example.push_back(v);
              piece[v] = p;
              queue.push_back(v);
              while (!queue.empty())
                {
                  const std::size_t u = queue.front();
                  queue.pop_front();
                  ++piece_size[p];
                  for_neighbours(labels, u, [&](const std::size_t w) {
                    if (state[w] == 1 && piece[w] < 0)
                      {
                        piece[w] = p;
                        queue.push_back(w);
                      }
                  });
                }
            }

        return pieces;
      }

      // Distance from @p x to the cut's box (0 inside).
      double
      distance_to_box(const Cut &cut, const Vec3 &x)
      {
        double squared = 0.;
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double out =
              std::max({cut.box_min[d] - x[d], x[d] - cut.box_max[d], 0.});
            squared += out * out;
          }
        return std::sqrt(squared);
      }

      // Why two segments share a piece: the shortest way through the uncut
      // bone from voxel @p from to voxel @p to, and where it passes a cut's
      // surface beyond the cut's box (a box that ends short of the bone
      // leaves a bridge there; one that fits the bone at one voxel size may
      // miss a sliver of it at another). Each passage is given to the cut
      // whose box is nearest.
      std::string
      describe_bridges(const LabelVolume               &labels,
                       const std::vector<std::uint8_t> &state,
                       const std::size_t                from,
                       const std::size_t                to,
                       const OsteotomyParameters       &prm)
      {
        const std::size_t  n         = labels.n_voxels();
        const auto        &size      = labels.size;
        const std::uint8_t unvisited = 255;
        // How each voxel was reached: the direction of the step (0-5).
        std::vector<std::uint8_t> step(n, unvisited);
        const long stride[3] = {1, long(size[0]), long(size[0] * size[1])};
        std::deque<std::size_t> queue{from};
        step[from] = 6;
        while (!queue.empty() && step[to] == unvisited)
          {
            const std::size_t u = queue.front();
            queue.pop_front();
            const std::size_t c[3] = {u % size[0],
                                      (u / size[0]) % size[1],
                                      u / (size[0] * size[1])};
            for (unsigned int d = 0; d < 3; ++d)
              for (const int sign : {-1, 1})
                {
                  if ((sign < 0 && c[d] == 0) ||
                      (sign > 0 && c[d] + 1 == size[d]))
                    continue;
                  const std::size_t w = u + sign * stride[d];
                  if (state[w] == 1 && step[w] == unvisited)
                    {
                      step[w] = 2 * d + (sign > 0);
                      queue.push_back(w);
                    }
                }
          }
        if (step[to] == unvisited)
          return "";

        const double kerf  = voxel_kerf(labels, prm);
        const auto   point = [&](const std::size_t v) {
          return labels.point(v % size[0],
                              (v / size[0]) % size[1],
                              v / (size[0] * size[1]));
        };
        // The cut whose surface (beyond its box) voxel v lies on, if any.
        const auto passed = [&](const std::size_t v) -> int {
          const Vec3 x    = point(v);
          int        cut  = -1;
          double     best = std::numeric_limits<double>::infinity();
          for (unsigned int c = 0; c < prm.cuts.size(); ++c)
            if (prm.cuts[c].surface_distance(x) < 0.5 * kerf &&
                distance_to_box(prm.cuts[c], x) < best)
              best = distance_to_box(prm.cuts[c], x), cut = c;
          return cut;
        };
        const auto tenth = [](const double x) {
          return std::round(10. * x) / 10.;
        };
        std::ostringstream s;
        s << " The bone joins them";
        int          previous = -1;
        unsigned int passages = 0;
        for (std::size_t v = to; step[v] != 6;)
          {
            const int cut = passed(v);
            if (cut >= 0 && cut != previous)
              {
                const Vec3 x = point(v);
                s << (passages++ ? "; " : ": ") << "across cut '"
                  << prm.cuts[cut].name << "' at (" << tenth(x[0]) << ", "
                  << tenth(x[1]) << ", " << tenth(x[2]) << "), "
                  << tenth(distance_to_box(prm.cuts[cut], x))
                  << " mm beyond its box";
              }
            previous             = cut;
            const unsigned int d = step[v] / 2;
            v = (step[v] % 2) ? v - stride[d] : v + stride[d];
          }
        if (passages == 0)
          return " The bone joins them without passing any cut's surface.";
        s << ". Enlarge the box to hold the bone there.";
        return s.str();
      }

      // Each segment's piece: the one at its seed, or the nearest bone
      // within 5 mm; every large piece must belong to a segment.
      std::map<int, unsigned int>
      assign_segments(const LabelVolume               &labels,
                      const std::vector<std::uint8_t> &state,
                      const Pieces                    &pieces,
                      const OsteotomyParameters       &prm,
                      const std::vector<SegmentSeed>  &segments)
      {
        const auto &size          = labels.size;
        const auto &piece         = pieces.piece;
        const auto &piece_size    = pieces.size;
        const auto &piece_example = pieces.example;
        const auto  describe      = [&](const std::size_t v) {
          const Vec3         x = labels.point(v % size[0],
                                      (v / size[0]) % size[1],
                                      v / (size[0] * size[1]));
          std::ostringstream s;
          s << "(" << std::round(x[0]) << ", " << std::round(x[1]) << ", "
            << std::round(x[2]) << ")";
          return s.str();
        };
        std::map<int, unsigned int> segment_of_piece;
        std::vector<std::size_t>    seed_voxel(segments.size());
        for (unsigned int s = 0; s < segments.size(); ++s)
          {
            const Vec3 &seed  = segments[s].point;
            const Vec3  c     = labels.continuous_index(seed);
            int         found = -1;
            double      best  = 5.;
            const int   r[3]  = {int(std::ceil(5. / labels.spacing[0])),
                                 int(std::ceil(5. / labels.spacing[1])),
                                 int(std::ceil(5. / labels.spacing[2]))};
            for (int dk = -r[2]; dk <= r[2]; ++dk)
              for (int dj = -r[1]; dj <= r[1]; ++dj)
                for (int di = -r[0]; di <= r[0]; ++di)
                  {
                    const long i = std::lround(c[0]) + di,
                               j = std::lround(c[1]) + dj,
                               k = std::lround(c[2]) + dk;
                    if (i < 0 || j < 0 || k < 0 || i >= long(size[0]) ||
                        j >= long(size[1]) || k >= long(size[2]))
                      continue;
                    const std::size_t v = labels.index(i, j, k);
                    if (piece[v] < 0)
                      continue;
                    const Vec3   x = labels.point(i, j, k);
                    const double d = std::sqrt(dot(sub(x, seed), sub(x, seed)));
                    if (d < best)
                      best = d, found = piece[v], seed_voxel[s] = v;
                  }
            if (found < 0)
              {
                std::ostringstream m;
                m << "Osteotomy: the seed point (" << seed[0] << ", " << seed[1]
                  << ", " << seed[2] << ") of segment '" << segments[s].name
                  << "' lies in no bone (none within 5 mm)."
                  << preview_hint(prm.scene_file);
                throw Error(m.str());
              }
            const auto taken = segment_of_piece.find(found);
            if (taken != segment_of_piece.end())
              throw Error(
                "Osteotomy: segments '" + segments[taken->second].name +
                "' and '" + segments[s].name +
                "' lie in one bone part: no cut separates them (check "
                "the cuts' positions and boxes, or the kerf)." +
                describe_bridges(labels,
                                 state,
                                 seed_voxel[taken->second],
                                 seed_voxel[s],
                                 prm) +
                preview_hint(prm.scene_file));
            segment_of_piece[found] = s;
          }
        const double voxel = labels.voxel_volume();
        for (std::size_t p = 0; p < piece_size.size(); ++p)
          if (!segment_of_piece.count(p) &&
              piece_size[p] * voxel >= prm.min_part_volume)
            {
              std::ostringstream m;
              m << "Osteotomy: a bone part of " << piece_size[p] * voxel / 1000.
                << " cm^3 (at " << describe(piece_example[p])
                << ") belongs to no segment; give it a segment with a seed "
                   "point "
                   "in it, or change the cuts."
                << preview_hint(prm.scene_file);
              throw Error(m.str());
            }

        return segment_of_piece;
      }
    } // namespace

    LabelVolume
    split_bone(const LabelVolume              &labels,
               const std::uint8_t              bone_label,
               const OsteotomyParameters      &prm,
               const std::vector<SegmentSeed> &segments)
    {
      if (segments.size() >= detached_flag)
        throw Error("Osteotomy: " + std::to_string(segments.size()) +
                    " segments; at most " + std::to_string(detached_flag - 1) +
                    ".");
      const std::size_t n      = labels.n_voxels();
      const BoneState   bone   = mark_kerfs(labels, bone_label, prm);
      const auto       &state  = bone.state;
      const Pieces      pieces = connected_pieces(labels, state);
      const auto        segment_of_piece =
        assign_segments(labels, state, pieces, prm, segments);

      // The parts, then the rest of the bone (kerfs, small pieces) to the
      // nearest part through the bone.
      std::deque<std::size_t> queue;
      LabelVolume             parts;
      parts.reinit_like(labels);
      for (std::size_t v = 0; v < n; ++v)
        if (pieces.piece[v] >= 0 && segment_of_piece.count(pieces.piece[v]))
          {
            parts.values[v] = segment_of_piece.at(pieces.piece[v]) + 1;
            queue.push_back(v);
          }
      while (!queue.empty())
        {
          const std::size_t u = queue.front();
          queue.pop_front();
          for_neighbours(labels, u, [&](const std::size_t w) {
            if (state[w] != 0 && parts.values[w] == 0)
              {
                parts.values[w] = parts.values[u];
                queue.push_back(w);
              }
          });
        }
      for (std::size_t v = 0; v < n; ++v)
        if (bone.detached[v] && parts.values[v] != 0)
          parts.values[v] |= detached_flag;
      return parts;
    }
  } // namespace Patient
} // namespace softface

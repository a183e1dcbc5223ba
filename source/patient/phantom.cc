// The synthetic head-and-neck CT (patient; Mollemans et al. 2007, Sec. 3.1): a
// parametric anatomy of implicit surfaces, its truth labels, and its
// acquisition as a CT volume in Hounsfield units (point spread, noise, optional
// metal streaks). Phantom patients take the same path through segmentation and
// meshing as real scans.

#include <softface/core/error.h>
#include <softface/patient/phantom.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      // Implicit primitives: about the signed distance (mm), negative inside.
      inline double
      ellipsoid(const Vec3 &x, const Vec3 &c, const Vec3 &r)
      {
        const double a = (x[0] - c[0]) / r[0], b = (x[1] - c[1]) / r[1],
                     d = (x[2] - c[2]) / r[2];
        return (std::sqrt(a * a + b * b + d * d) - 1.) *
               std::min({r[0], r[1], r[2]});
      }

      // Distance to the segment a-b in a frame scaled by s, minus r.
      inline double
      capsule(const Vec3  &x,
              const Vec3  &a,
              const Vec3  &b,
              const double r,
              const Vec3  &s = {{1., 1., 1.}})
      {
        double ab[3], ax[3], dot = 0., len2 = 0.;
        for (unsigned int d = 0; d < 3; ++d)
          {
            ab[d] = b[d] - a[d];
            ax[d] = x[d] - a[d];
            dot += ax[d] * ab[d];
            len2 += ab[d] * ab[d];
          }
        const double t = std::clamp(dot / len2, 0., 1.);
        double       n = 0.;
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double v = (ax[d] - t * ab[d]) / s[d];
            n += v * v;
          }
        return std::sqrt(n) * std::min({s[0], s[1], s[2]}) - r;
      }

      // Polynomial smooth minimum (union) and maximum (intersection).
      inline double
      smin(const double a, const double b, const double k)
      {
        const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0., 1.);
        return b * (1. - h) + a * h - k * h * (1. - h);
      }

      inline double
      smax(const double a, const double b, const double k)
      {
        return -smin(-a, -b, k);
      }

      // A dental arch: capsules along y = y0 + a x^2, |x| <= half, between
      // the heights z_low and z_high (flattened vertically by the scale).
      double
      arch(const Vec3  &x,
           const double y0,
           const double a,
           const double z_low,
           const double z_high,
           const double half,
           const double r)
      {
        // Far from its bounding box the arch does not matter.
        if (std::abs(x[0]) > half + r + 4. || x[2] < z_low - 4. ||
            x[2] > z_high + 4. || x[1] < y0 - r - 4. ||
            x[1] > y0 + a * half * half + r + 4.)
          return 10.;
        const double zc = 0.5 * (z_low + z_high), hz = 0.5 * (z_high - z_low);
        double       d = 1e9;
        const int    n = 12;
        for (int s = 0; s < n; ++s)
          {
            const double x0 = -half + 2. * half * s / n,
                         x1 = -half + 2. * half * (s + 1) / n;
            d               = std::min(d,
                         capsule(x,
                                 {{x0, y0 + a * x0 * x0, zc}},
                                 {{x1, y0 + a * x1 * x1, zc}},
                                 r,
                                 {{1., 1., hz / r}}));
          }
        return d;
      }

      // Rotate p about c in the (y, z) plane by angle (radians; positive
      // turns +y towards -z, i.e. a forward point downwards).
      Vec3
      rotate_yz(const Vec3 &p, const Vec3 &c, const double angle)
      {
        const double dy = p[1] - c[1], dz = p[2] - c[2];
        const double cs = std::cos(angle), sn = std::sin(angle);
        return {{p[0], c[1] + cs * dy + sn * dz, c[2] - sn * dy + cs * dz}};
      }

      constexpr double occlusion = -20.; // occlusal plane, z

      // Where a point of the face lies in the phantom's unscaled frame: the
      // lower face scales in height by H about the occlusal plane, and the
      // scaling fades out between z = 10 and 40 mm, so that the face joins
      // the unscaled forehead without a step.
      inline Vec3
      lower_face(const Vec3 &p, const double H)
      {
        const double w = std::clamp((40. - p[2]) / 30., 0., 1.);
        Vec3         x = p;
        x[2]           = p[2] - w * (1. - 1. / H) * (p[2] - occlusion);
        return x;
      }
      constexpr double skin_depth = 2.; // mm under the skin surface
      constexpr double fat_depth  = 6.; // skin + subcutaneous fat
    }                                   // namespace

    const std::vector<double> &
    Phantom::hounsfield_units()
    {
      // air, skin, fat, muscle, bone, mandible, teeth, brain
      static const std::vector<double> hu = {
        -1000., 40., -100., 45., 1100., 1100., 2000., 35.};
      return hu;
    }

    Phantom::Phantom(const PhantomParameters &parameters)
        : prm(parameters)
    {
      const double W = prm.face_width;
      // The mandible: rami from the condyles down to the gonia, the body
      // forward to the symphysis, scaled by its length, turned by its
      // angle about the gonia, and moved by the profile.
      condyle_right = {{-50. * W, 16., 7.}};
      condyle_left  = {{50. * W, 16., 7.}};
      gonion_right  = {{-46. * W, 10., -60.}};
      gonion_left   = {{46. * W, 10., -60.}};
      const double profile_shift =
        prm.profile == "class II" ?
          -prm.jaw_discrepancy :
          (prm.profile == "class III" ? prm.jaw_discrepancy : 0.);
      const double turn  = (prm.mandible_angle - 120.) * M_PI / 180.;
      const auto   place = [&](const Vec3 &gonion, const Vec3 &p0) {
        Vec3 p;
        for (unsigned int d = 0; d < 3; ++d)
          p[d] = gonion[d] + prm.mandible_length * (p0[d] - gonion[d]);
        p = rotate_yz(p, gonion, -turn);
        p[1] -= profile_shift * (gonion[1] - p[1]) / (gonion[1] + 62.);
        return p;
      };
      body_right         = place(gonion_right, {{-30. * W, -38., -52.}});
      body_left          = place(gonion_left, {{30. * W, -38., -52.}});
      symphysis_point    = place(gonion_left, {{0., -62., -52.}});
      symphysis_point[0] = 0.;
      chin_advance       = -(symphysis_point[1] - (-62.));
      chin_drop          = -(symphysis_point[2] - (-52.));
    }

    Vec3
    Phantom::condyle(const int side) const
    {
      return side < 0 ? condyle_right : condyle_left;
    }

    Vec3
    Phantom::gonion(const int side) const
    {
      return side < 0 ? gonion_right : gonion_left;
    }

    Vec3
    Phantom::symphysis() const
    {
      return symphysis_point;
    }

    double
    Phantom::occlusal_plane() const
    {
      return occlusion;
    }

    double
    Phantom::skin_function(const Vec3 &p) const
    {
      const double W = prm.face_width, H = prm.face_height;
      const double t = prm.soft_tissue_thickness;
      const Vec3   x = lower_face(p, H);
      const double a = chin_advance, dz = chin_drop / H;

      double f = ellipsoid(p, {{0., 15., 75.}}, {{77., 97., 82.}}); // scalp
      f =
        smin(f, ellipsoid(x, {{0., -28., 0.}}, {{60. * W, 60., 62.}}) - t, 12.);
      f = smin(f, capsule(p, {{0., 25., -125.}}, {{0., 12., -30.}}, 52.), 15.);
      for (const int s : {-1, 1})
        f = smin(f,
                 ellipsoid(x, {{s * 42. * W, -50., 8.}}, {{22., 24., 28.}}) - t,
                 8.);
      f = smin(f, ellipsoid(x, {{0., -98., 20.}}, {{12., 18., 22.}}) - t, 6.);
      f = smin(f, ellipsoid(x, {{0., -86., 42.}}, {{9., 8., 16.}}) - t, 6.);
      f =
        smin(f, ellipsoid(x, {{0., -84., -12.}}, {{24. * W, 8., 8.}}) - t, 4.);
      f =
        smin(f,
             ellipsoid(x, {{0., -82. - a, -29. - dz}}, {{22. * W, 8., 8.}}) - t,
             4.);
      f =
        smin(f,
             ellipsoid(x, {{0., -66. - a, -62. - dz}}, {{26. * W, 16., 20.}}) -
               t,
             8.);
      // The masseters over the rami and the soft tissue along the
      // mandible's body: the jaw is covered by about a centimetre.
      for (const int side : {-1, 1})
        {
          const Vec3 c = condyle(side), g = gonion(side);
          const Vec3 b = side < 0 ? body_right : body_left;
          f            = smin(f,
                   capsule(p,
                           {{c[0] + side * 2., c[1] - 1., c[2] - 2.}},
                           {{g[0] + side * 2., g[1] - 1., g[2] + 2.}},
                           14.) -
                     t,
                   10.);
          f            = smin(f, capsule(p, g, b, 11.) - t, 10.);
          f            = smin(f, capsule(p, b, symphysis_point, 11.) - t, 10.);
        }
      // At least 3 mm of soft tissue over the mandible everywhere.
      f = smin(f, mandible_function(p) - 3., 4.);
      // The mouth slit separates the lips down to the front teeth; closed
      // lips meet.
      if (prm.closed_mouth)
        return f;
      const double slit = std::max({std::abs(x[2] - occlusion) - 1.5,
                                    std::abs(x[0]) - 22. * W,
                                    x[1] + 74.});
      return std::max(f, -slit);
    }

    double
    Phantom::brain_function(const Vec3 &x) const
    {
      return ellipsoid(x, {{0., 15., 75.}}, {{63., 83., 68.}});
    }

    double
    Phantom::bone_function(const Vec3 &p) const
    {
      const double W = prm.face_width, H = prm.face_height;
      const Vec3   x = lower_face(p, H);
      const double cranium =
        std::max(ellipsoid(p, {{0., 15., 75.}}, {{70., 90., 75.}}),
                 -brain_function(p));
      double f = smin(cranium,
                      ellipsoid(x, {{0., -38., 25.}}, {{52. * W, 40., 36.}}),
                      8.);
      for (const int s : {-1, 1}) // orbits
        f = std::max(
          f, -ellipsoid(p, {{s * 32. * W, -66., 45.}}, {{16., 16., 15.}}));
      // The upper alveolar process holds the teeth's roots.
      const double alveolus = arch({{p[0] / W, p[1], p[2]}},
                                   -66.,
                                   0.025,
                                   occlusion + 6. * prm.face_height,
                                   occlusion + 24. * prm.face_height,
                                   30.,
                                   6.5);
      return smin(f, alveolus, 3.);
    }

    double
    Phantom::upper_teeth_function(const Vec3 &p) const
    {
      const double W = prm.face_width;
      return arch({{p[0] / W, p[1], p[2]}},
                  -68.,
                  0.025,
                  occlusion + teeth_gap(),
                  occlusion + 12. * prm.face_height,
                  28.,
                  4.);
    }

    double
    Phantom::lower_teeth_function(const Vec3 &p) const
    {
      const double W = prm.face_width;
      // The lower teeth ride on the mandible's front; in occlusion they
      // reach the occlusal plane wherever the mandible's shape put them.
      return arch({{p[0] / W, p[1] + chin_advance, p[2] + chin_drop}},
                  -66.,
                  0.025,
                  occlusion - 12. * prm.face_height,
                  occlusion - teeth_gap() + (prm.closed_mouth ? chin_drop : 0.),
                  26.,
                  3.8);
    }

    double
    Phantom::mandible_function(const Vec3 &x) const
    {
      // Far from the jaw nothing needs evaluating.
      if (x[2] > 40. || x[2] < -120. || x[1] > 60.)
        return 10.;
      const Vec3 scale{{1., 1., 2.}};
      double     f = std::min({capsule(x, gonion_right, body_right, 6.5, scale),
                               capsule(x, body_right, symphysis_point, 6.5, scale),
                               capsule(x, symphysis_point, body_left, 6.5, scale),
                               capsule(x, body_left, gonion_left, 6.5, scale)});
      for (const int s : {-1, 1})
        {
          const Vec3 &g = gonion(s), &c = condyle(s);
          f = smin(
            f,
            capsule(x, g, {{c[0], c[1], c[2] - 6.}}, 6., {{0.55, 1.8, 1.}}),
            4.);
          f = smin(f, ellipsoid(x, c, {{9., 6., 6.}}), 3.);
        }
      // The lower alveolar process, riding on the mandible's front.
      const double W = prm.face_width;
      f              = smin(f,
               arch({{x[0] / W, x[1] + chin_advance, x[2] + chin_drop}},
                    -64.,
                    0.025,
                    occlusion - 26. * prm.face_height,
                    occlusion - 6. * prm.face_height,
                    28.,
                    6.),
               3.);
      return smin(f, lower_teeth_function(x), 1.);
    }

    std::uint8_t
    Phantom::label(const Vec3 &x) const
    {
      const double s = skin_function(x);
      if (s > 0.)
        return air;
      if (upper_teeth_function(x) < 0. || lower_teeth_function(x) < 0.)
        return teeth;
      if (mandible_function(x) < 0.)
        return mandible;
      if (bone_function(x) < 0.)
        return bone;
      if (brain_function(x) < 0.)
        return brain;
      if (s > -skin_depth)
        return skin;
      if (s > -fat_depth - 0.5 * prm.soft_tissue_thickness)
        return fat;
      return muscle;
    }

    CTVolume
    Phantom::grid() const
    {
      CTVolume ct;
      for (unsigned int d = 0; d < 3; ++d)
        {
          ct.size[d]    = std::max<std::size_t>(2,
                                             std::lround(prm.field_of_view[d] /
                                                         prm.voxel_size));
          ct.spacing[d] = prm.voxel_size;
          ct.origin[d] =
            prm.centre[d] - 0.5 * (ct.size[d] - 1) * prm.voxel_size;
        }
      // The stages hold about 40 bytes a voxel: refuse what no machine of
      // ours holds instead of running out of memory half-way.
      const double n_voxels = double(ct.size[0]) * ct.size[1] * ct.size[2];
      if (n_voxels > max_voxels)
        throw Error("Scene/Patient/Phantom: 'Field of view' / 'Voxel size' "
                    "make " +
                    std::to_string(ct.size[0]) + " x " +
                    std::to_string(ct.size[1]) + " x " +
                    std::to_string(ct.size[2]) + " voxels, more than " +
                    std::to_string(max_voxels / 1000000) +
                    " million; use larger voxels or a smaller field of view.");
      return ct;
    }

    void
    Phantom::acquire(CTVolume &ct, LabelVolume &truth) const
    {
      acquire(grid(), ct, truth);
    }

    void
    Phantom::acquire(const CTVolume &grid,
                     CTVolume       &ct,
                     LabelVolume    &truth) const
    {
      ct.reinit_like(grid);
      truth.reinit_like(ct);

      // Labels at voxel centres, slab by slab on every core.
      const std::size_t  nk = ct.size[2];
      const unsigned int n_threads =
        std::max(1u, std::min(4u, std::thread::hardware_concurrency()));
      std::vector<std::thread> threads;
      for (unsigned int t = 0; t < n_threads; ++t)
        threads.emplace_back([&, t]() {
          for (std::size_t k = t; k < nk; k += n_threads)
            for (std::size_t j = 0; j < ct.size[1]; ++j)
              for (std::size_t i = 0; i < ct.size[0]; ++i)
                truth(i, j, k) = label(ct.point(i, j, k));
        });
      for (auto &thread : threads)
        thread.join();

      // Hounsfield units with the partial-volume effect of a real scanner:
      // where the tissue changes within a voxel, its value is the mean over
      // 3 x 3 x 3 points inside it, so that the image places a surface to a
      // fraction of a voxel. Then the point spread (a separable Gaussian)
      // and noise.
      const auto        &hu = hounsfield_units();
      std::vector<float> image(ct.n_voxels());
      for (std::size_t v = 0; v < image.size(); ++v)
        image[v] = hu[truth.values[v]];
      threads.clear();
      for (unsigned int t = 0; t < n_threads; ++t)
        threads.emplace_back([&, t]() {
          for (std::size_t k = t; k < nk; k += n_threads)
            for (std::size_t j = 0; j < ct.size[1]; ++j)
              for (std::size_t i = 0; i < ct.size[0]; ++i)
                {
                  const auto l     = truth(i, j, k);
                  bool       mixed = false;
                  if (i > 0 && i + 1 < ct.size[0] && j > 0 &&
                      j + 1 < ct.size[1] && k > 0 && k + 1 < nk)
                    mixed =
                      truth(i - 1, j, k) != l || truth(i + 1, j, k) != l ||
                      truth(i, j - 1, k) != l || truth(i, j + 1, k) != l ||
                      truth(i, j, k - 1) != l || truth(i, j, k + 1) != l;
                  if (!mixed)
                    continue;
                  double sum = 0.;
                  for (const double a : {-1. / 3., 0., 1. / 3.})
                    for (const double b : {-1. / 3., 0., 1. / 3.})
                      for (const double c : {-1. / 3., 0., 1. / 3.})
                        sum += hu[label(ct.point(i + a, j + b, k + c))];
                  image[ct.index(i, j, k)] = sum / 27.;
                }
        });
      for (auto &thread : threads)
        thread.join();

      if (prm.metal_streaks)
        {
          // Fillings in the first molars; each casts radial streaks in the
          // axial slices through it, fading with distance and height.
          const double            W        = prm.face_width;
          const std::vector<Vec3> fillings = {
            {{-22. * W, -50., occlusion + 5.}},
            {{22. * W, -50., occlusion + 5.}},
            {{-21. * W, -48. - chin_advance, occlusion - 5. - chin_drop}},
            {{21. * W, -48. - chin_advance, occlusion - 5. - chin_drop}}};
          for (std::size_t k = 0; k < ct.size[2]; ++k)
            for (std::size_t j = 0; j < ct.size[1]; ++j)
              for (std::size_t i = 0; i < ct.size[0]; ++i)
                {
                  const Vec3 x = ct.point(i, j, k);
                  float     &v = image[ct.index(i, j, k)];
                  for (const Vec3 &c : fillings)
                    {
                      const double dz = x[2] - c[2];
                      if (std::abs(dz) > 8.)
                        continue;
                      const double dx = x[0] - c[0], dy = x[1] - c[1];
                      const double r = std::sqrt(dx * dx + dy * dy);
                      if (r < 2.5 && std::abs(dz) < 2.)
                        v = 3000.f;
                      else if (r < 90.)
                        v += 900. * std::cos(10. * std::atan2(dy, dx)) *
                             std::exp(-r / 30. - dz * dz / 8.);
                    }
                }
        }

      if (prm.blur > 0.)
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double sigma  = prm.blur / ct.spacing[d];
            const int    radius = std::max(1, int(std::ceil(3. * sigma)));
            std::vector<double> w(2 * radius + 1);
            double              sum = 0.;
            for (int q = -radius; q <= radius; ++q)
              sum += (w[q + radius] = std::exp(-0.5 * q * q / (sigma * sigma)));
            for (auto &x : w)
              x /= sum;
            const std::size_t stride =
              d == 0 ? 1 : (d == 1 ? ct.size[0] : ct.size[0] * ct.size[1]);
            const long                        n = ct.size[d];
            std::vector<float>                line(n);
            const std::array<std::size_t, 3> &sz = ct.size;
            for (std::size_t v = 0; v < image.size(); ++v)
              {
                // Visit each line once, from its first voxel.
                const std::size_t coordinate =
                  d == 0 ? v % sz[0] :
                           (d == 1 ? (v / sz[0]) % sz[1] : v / (sz[0] * sz[1]));
                if (coordinate != 0)
                  continue;
                for (long q = 0; q < n; ++q)
                  line[q] = image[v + q * stride];
                for (long q = 0; q < n; ++q)
                  {
                    double s = 0.;
                    for (int o = -radius; o <= radius; ++o)
                      s +=
                        w[o + radius] * line[std::clamp<long>(q + o, 0, n - 1)];
                    image[v + q * stride] = s;
                  }
              }
          }

      std::mt19937                     random(prm.seed);
      std::normal_distribution<double> gaussian(0., prm.noise);
      for (std::size_t v = 0; v < image.size(); ++v)
        {
          const double value =
            image[v] + (prm.noise > 0. ? gaussian(random) : 0.);
          ct.values[v] = static_cast<std::int16_t>(
            std::clamp(std::round(value), -1024., 3071.));
        }
    }
  } // namespace Patient
} // namespace softface

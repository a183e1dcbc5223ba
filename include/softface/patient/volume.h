#ifndef softface_patient_volume_h
#define softface_patient_volume_h

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace softface
{
  namespace Patient
  {
    using Vec3 = std::array<double, 3>;

    /**
     * A 3D image on a regular grid, as the patient stages hand it to each
     * other (CT in Hounsfield units, labels). The physical position of voxel
     * (i, j, k) is origin + D (spacing * (i, j, k)), with D the direction
     * cosines (row-major), as ITK defines it; every stage works in this one
     * physical frame (mm). Plain data, so that the ITK, VTK and CGAL parts
     * of softface exchange images without including each other's headers.
     */
    template <typename T>
    struct Volume
    {
      std::array<std::size_t, 3> size{{0, 0, 0}};
      Vec3                       spacing{{1., 1., 1.}};
      Vec3                       origin{{0., 0., 0.}};
      std::array<double, 9> direction{{1., 0., 0., 0., 1., 0., 0., 0., 1.}};
      std::vector<T>        values;

      /// The same grid (size, spacing, origin, direction), values zero.
      template <typename U>
      void
      reinit_like(const Volume<U> &other)
      {
        size      = other.size;
        spacing   = other.spacing;
        origin    = other.origin;
        direction = other.direction;
        values.assign(n_voxels(), T());
      }

      std::size_t
      n_voxels() const
      {
        return size[0] * size[1] * size[2];
      }

      std::size_t
      index(const std::size_t i, const std::size_t j, const std::size_t k) const
      {
        return i + size[0] * (j + size[1] * k);
      }

      T &
      operator()(const std::size_t i, const std::size_t j, const std::size_t k)
      {
        return values[index(i, j, k)];
      }

      const T &
      operator()(const std::size_t i,
                 const std::size_t j,
                 const std::size_t k) const
      {
        return values[index(i, j, k)];
      }

      /// Physical position of voxel (i, j, k) (continuous indices allowed).
      Vec3
      point(const double i, const double j, const double k) const
      {
        const double s[3] = {i * spacing[0], j * spacing[1], k * spacing[2]};
        Vec3         x;
        for (unsigned int r = 0; r < 3; ++r)
          x[r] = origin[r] + direction[3 * r] * s[0] +
                 direction[3 * r + 1] * s[1] + direction[3 * r + 2] * s[2];
        return x;
      }

      /// Continuous index of a physical point (inverse of point()).
      Vec3
      continuous_index(const Vec3 &x) const
      {
        // D is orthonormal: its inverse is its transpose.
        const double d[3] = {x[0] - origin[0],
                             x[1] - origin[1],
                             x[2] - origin[2]};
        Vec3         ijk;
        for (unsigned int c = 0; c < 3; ++c)
          ijk[c] = (direction[c] * d[0] + direction[3 + c] * d[1] +
                    direction[6 + c] * d[2]) /
                   spacing[c];
        return ijk;
      }

      /// Volume of one voxel in mm^3.
      double
      voxel_volume() const
      {
        return spacing[0] * spacing[1] * spacing[2];
      }

      /// The voxel nearest to @p x, or false if it lies outside the grid.
      bool
      nearest_voxel(const Vec3 &x, std::array<std::size_t, 3> &ijk) const
      {
        const Vec3 c = continuous_index(x);
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double r = std::round(c[d]);
            if (!(r >= 0. && r < double(size[d])))
              return false;
            ijk[d] = static_cast<std::size_t>(r);
          }
        return true;
      }
    };

    using CTVolume    = Volume<std::int16_t>;
    using LabelVolume = Volume<std::uint8_t>;
  } // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_surface_h
#define softface_patient_surface_h

#include <softface/patient/volume.h>

#include <array>
#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// A triangulated surface in the patient frame (mm).
    struct TriangleSurface
    {
      std::vector<Vec3>                        points;
      std::vector<std::array<unsigned int, 3>> triangles;

      /// Sum of the triangles' areas (mm^2).
      double
      area() const;
    };

    /**
     * The iso-surface of @p volume at @p value (marching cubes: VTK's flying
     * edges, with the linear interpolation between voxel centres that puts
     * it within a fraction of a voxel of the true surface), in the volume's
     * physical frame. With @p largest_piece only its largest connected piece
     * (the skin without loose bits), else every piece of at least
     * @p min_points points.
     */
    TriangleSurface
    iso_surface(const Volume<float> &volume,
                const double         value,
                const bool           largest_piece,
                const unsigned int   min_points = 100);

    /// Written by the file name's extension: .ply (binary) or .vtp.
    void
    write_surface(const TriangleSurface &surface, const std::string &filename);

    /// Values at the points of a surface (1 or 3 components), for .vtp.
    struct PointField
    {
      std::string         name;
      unsigned int        components = 1;
      std::vector<double> values; ///< components per point, point by point
    };

    /// As above; .vtp files also carry @p fields (a .ply only the surface).
    void
    write_surface(const TriangleSurface         &surface,
                  const std::string             &filename,
                  const std::vector<PointField> &fields);

    /// Read a .ply or .vtp surface (triangles; other polygons are refused).
    TriangleSurface
    read_surface(const std::string &filename);
  } // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_icp_h
#define softface_patient_icp_h

#include <softface/patient/volume.h>

#include <array>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// A rigid motion x -> R x + t (R a rotation, row-major).
    struct RigidTransform
    {
      std::array<double, 9> rotation{{1., 0., 0., 0., 1., 0., 0., 0., 1.}};
      Vec3                  translation{{0., 0., 0.}};

      Vec3
      operator()(const Vec3 &x) const;
      /// This after @p first: x -> this(first(x)).
      RigidTransform
      after(const RigidTransform &first) const;
      RigidTransform
      inverse() const;
      /// Angle of the rotation in degrees.
      double
      angle_degrees() const;
      /// The rotation's unit axis (any unit vector for the identity).
      Vec3
      axis() const;
      /// Rotation by @p angle_degrees about @p axis through @p centre, then
      /// the translation (the Planning's x -> R (x - c) + c + t).
      static RigidTransform
      from_planning(const Vec3  &translation,
                    const Vec3  &axis,
                    const double angle_degrees,
                    const Vec3  &centre);
    };

    struct IcpParameters
    {
      unsigned int max_iterations = 200;
      /// Stop when an iteration moves no moving point by more than this (mm).
      double tolerance = 1e-5;
      /// Pairs farther apart than this are left out (mm): the moving part
      /// matches only its own patch of the fixed cloud. Halved down to
      /// 'Final rejection distance' as the fit converges.
      double rejection_distance       = 10.;
      double final_rejection_distance = 2.;
    };

    struct IcpResult
    {
      RigidTransform transform;       ///< maps the moving points onto the fixed
      double         rms        = 0.; ///< over the accepted pairs, mm
      unsigned int   iterations = 0;
      std::size_t    n_pairs    = 0; ///< accepted pairs in the last iteration
      bool           converged  = false;
    };

    /**
     * Iterative closest points (Besl and McKay; Mollemans et al. 2007,
     * Sec. 3.2, refines a manual start with it): the rigid motion that carries
     * @p moving onto the cloud @p fixed, from @p initial. Each iteration pairs
     * every moved point with its closest fixed point (a nanoflann k-d tree
     * built once), drops pairs farther than the rejection distance, and solves
     * the best rigid fit of the pairs in closed form (SVD of the
     * cross-covariance, Eigen). Throws an Error if fewer than three pairs
     * remain.
     */
    IcpResult
    icp(const std::vector<Vec3> &moving,
        const std::vector<Vec3> &fixed,
        const RigidTransform    &initial,
        const IcpParameters     &parameters);
  } // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_registration_h
#define softface_patient_registration_h

#include <softface/patient/icp.h>
#include <softface/patient/surface.h>
#include <softface/patient/volume.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /// An axis-aligned box in the physical frame (mm).
    struct Box
    {
      Vec3 lower{{0., 0., 0.}};
      Vec3 upper{{0., 0., 0.}};

      /// True if the box has no extent in some direction.
      bool
      empty() const;
      Vec3
      centre() const;
    };

    /**
     * 'x0, y0, z0; x1, y1, z1': the box with these two opposite corners
     * (in any order). Anything else, or a box of no extent in some
     * direction, is an Error naming @p where.
     */
    Box
    parse_box(const std::string &text, const std::string &where);

    struct RegistrationParameters
    {
      /**
       * The unaltered subvolume (Mollemans et al. 2007, 3.5.1: typically
       * the top of the skull), in the pre-operative CT's frame; the part of
       * it inside the CT is used (the voxels whose centres lie in it). No
       * box: the whole pre-operative CT.
       */
      std::optional<Box> subvolume;

      /// How the metric is restricted to the subvolume.
      enum class Restriction
      {
        crop, ///< the pre-operative CT cropped to it (RegionOfInterest)
        mask  ///< the whole pre-operative CT with a fixed-image mask
      };
      Restriction restriction = Restriction::crop;

      /// Where the optimisation starts (CenteredTransformInitializer).
      enum class Initializer
      {
        identity, ///< the scanner frames agree: no motion
        geometry, ///< the centres of the two CTs' fields of view
        moments   ///< the centres of mass of the two CTs (HU + 1000 >= 0)
      };
      Initializer initializer = Initializer::identity;

      unsigned int histogram_bins = 50;
      /**
       * At most this many sample points per level: where the subvolume
       * holds more voxels, the metric takes every k-th one (ITK's regular
       * sampling, each point jittered by a Gaussian of a third of a voxel
       * drawn by a generator seeded with @p seed, so the same points every
       * run). 0: every voxel, unjittered.
       */
      std::size_t  samples = 100000;
      unsigned int seed    = 1;

      /// The multi-resolution schedule, coarse to fine: shrink factors
      /// and Gaussian smoothing (sigma, mm), one per level.
      std::vector<unsigned int> shrink_factors{{4, 2, 1}};
      std::vector<double>       smoothing_sigmas{{4., 2., 0.}};

      /// The optimiser, on parameters scaled by the physical shift each
      /// causes at the subvolume's corners
      /// (RegistrationParameterScalesFromPhysicalShift).
      enum class Optimizer
      {
        /// Regular step gradient descent: the first step of the first
        /// level @p learning_rate (parameter units: about mm), of a later
        /// level that times its shrink factor over the first level's (a
        /// fine level starts from the coarse result, a coarse voxel's
        /// worth away at most); times @p relaxation at every change of
        /// direction, down to @p minimum_step.
        regular_step,
        /// Conjugate gradients (Polak-Ribiere) with a golden-section
        /// line search; the first step moves no voxel by more than
        /// @p learning_rate mm (scaled per level as above); a level ends
        /// when the metric's trend over the last @p convergence_window
        /// iterations falls below @p convergence.
        conjugate_gradient
      };
      Optimizer    optimizer          = Optimizer::regular_step;
      double       learning_rate      = 2.;
      double       minimum_step       = 1e-4;
      double       relaxation         = 0.5;
      double       convergence        = 1e-6;
      unsigned int convergence_window = 10;
      /// At most this many iterations per level.
      unsigned int max_iterations = 300;

      /// Threads of the metric. With one the result is the same bit for
      /// bit from run to run; ITK's Mattes metric sums its derivative
      /// over threads in the order they finish, so with more the last
      /// digits vary.
      unsigned int threads = 1;
    };

    /// What one level of the schedule did.
    struct RegistrationLevel
    {
      unsigned int shrink_factor   = 1;
      double       smoothing_sigma = 0.; ///< mm
      double       learning_rate   = 0.; ///< its first step
      unsigned int iterations      = 0;
      double       metric          = 0.; ///< at the level's end
      std::string  stop;                 ///< ITK's stop condition
    };

    struct RegistrationResult
    {
      /// x_pre = R x_post + t: carries post-operative points (surfaces
      /// made from the post-operative CT) into the pre-operative frame.
      RigidTransform post_to_pre;
      /// Its inverse, ITK's transform (fixed pre-operative points to
      /// moving post-operative ones) as a VersorRigid3DTransform:
      /// x_post = V (x_pre - centre) + centre + itk_translation.
      Vec3                  centre{{0., 0., 0.}};
      std::array<double, 4> versor{{0., 0., 0., 1.}}; ///< x, y, z, w
      Vec3                  itk_translation{{0., 0., 0.}};
      double                angle_degrees = 0.; ///< of the rotation

      /// Mattes mutual information (ITK's sign: negative, lower is
      /// better) at the result on the finest level.
      double                         metric = 0.;
      std::vector<RegistrationLevel> levels;

      /// The voxels of the pre-operative CT the metric saw (the
      /// subvolume's part inside the CT) and their physical extent
      /// (voxel centres).
      std::array<std::size_t, 3> subvolume_voxels{{0, 0, 0}};
      Box                        subvolume;
    };

    /**
     * Rigid registration of the post-operative CT (moving) to the
     * pre-operative CT (fixed) by maximisation of mutual information on an
     * unaltered subvolume (Maes et al. 1997; Mollemans et al. 2007, 3.5.1),
     * with ITK's registration framework v4: Mattes mutual information,
     * a versor rigid transform rotating about the subvolume's centre,
     * regular step gradient descent with scales from the physical shift
     * of each parameter at the subvolume's corners (for the mask too, whose
     * metric domain is the whole CT), and a multi-resolution schedule (each
     * level's first step scaled by its shrink factor). Errors (a subvolume
     * empty, outside the CT or too thin for the schedule, a schedule of
     * unequal lengths, a registration that fails) are one line.
     */
    RegistrationResult
    register_rigid(const CTVolume               &pre_operative,
                   const CTVolume               &post_operative,
                   const RegistrationParameters &parameters);

    /**
     * @p image resampled on @p grid after moving its content by
     * @p image_to_grid: out(x) = image(image_to_grid^-1 (x)) (linear
     * interpolation, @p outside where that falls outside @p image). The
     * post-operative CT in the pre-operative frame is
     * resample(post, result.post_to_pre, pre).
     */
    CTVolume
    resample(const CTVolume       &image,
             const RigidTransform &image_to_grid,
             const CTVolume       &grid,
             const double          outside = -1024.);

    /// Every point of @p surface moved by @p transform (the triangles
    /// keep their orientation: a rotation does not mirror).
    TriangleSurface
    transform_surface(const TriangleSurface &surface,
                      const RigidTransform  &transform);

    /**
     * The result as a small CSV text (one quantity per line: name, then
     * its values; lines starting with '#' explain the conventions), what
     * 'softface register' prints and writes.
     */
    std::string
    registration_table(const RegistrationResult &result);
  } // namespace Patient
} // namespace softface

#endif

#ifndef softface_patient_phantom_h
#define softface_patient_phantom_h

#include <deal.II/base/parameter_handler.h>

#include <softface/patient/volume.h>

#include <string>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * What a phantom patient looks like: anatomy parameters that vary
     * between patients, and how its CT volume is acquired. Lengths in mm.
     * The patient frame is LPS (x to the patient's left, y posterior, z
     * superior; the face looks towards -y), the occlusal plane at z = -20
     * and the head's mid-sagittal plane at x = 0.
     */
    struct PhantomParameters
    {
      /// Subsection "Phantom" (the handler is where it should be).
      static void
      declare_parameters(dealii::ParameterHandler &prm);
      void
      parse_parameters(dealii::ParameterHandler &prm);

      double voxel_size = 1.;
      Vec3   field_of_view{{180., 240., 256.}};
      Vec3   centre{{0., -5., 0.}};

      double face_width            = 1.;   ///< scales the face in x
      double face_height           = 1.;   ///< scales the lower face in z
      double soft_tissue_thickness = 0.;   ///< added to the facial soft tissue
      double mandible_length       = 1.;   ///< scales gonion -> symphysis
      double mandible_angle        = 120.; ///< gonial angle, degrees
      /// "class I", "class II" (retrognathic) or "class III" (prognathic).
      std::string profile         = "class I";
      double      jaw_discrepancy = 6.; ///< mm, for class II and III
      /// Teeth in occlusion and lips together, as most patients are
      /// scanned; else the teeth and the lips part by 3 mm.
      bool closed_mouth = false;

      double       noise         = 15.; ///< HU, standard deviation
      double       blur          = 0.5; ///< mm, Gaussian point spread
      bool         metal_streaks = false;
      unsigned int seed          = 1;
    };

    /**
     * A synthetic head and neck (a patient like that of Mollemans et al. 2007,
     * Sec. 3.1, made up): cranium with the brain inside, orbits, maxilla with
     * the upper teeth, mandible (body, rami, condyles) with the lower teeth,
     * chin; soft tissue of skin, fat and muscle over it (masseters over the
     * rami), nose, cheeks, upper and lower lips, neck; air around. Every
     * structure is an implicit surface (negative inside), so the anatomy is
     * smooth and closed at any voxel size. The temporomandibular joints leave
     * gaps of a few mm; the teeth and the lips part by 3 mm (the mouth slit)
     * or, with a closed mouth, meet on the occlusal plane.
     */
    class Phantom
    {
    public:
      /// Truth labels of the phantom (what segmentation should recover).
      enum Label : std::uint8_t
      {
        air      = 0,
        skin     = 1,
        fat      = 2,
        muscle   = 3,
        bone     = 4, ///< cranium and midface (maxilla, zygomas)
        mandible = 5,
        teeth    = 6,
        brain    = 7
      };

      /// Hounsfield units of each label (air ... brain).
      static const std::vector<double> &
      hounsfield_units();

      explicit Phantom(const PhantomParameters &parameters);

      /// Implicit skin surface: about the signed distance, negative inside.
      double
      skin_function(const Vec3 &x) const;

      /// The truth label at a point.
      std::uint8_t
      label(const Vec3 &x) const;

      /**
       * The CT volume in Hounsfield units (labels sampled at voxel centres,
       * averaged over 27 points in the voxels where they change (partial
       * volume), blurred by the point spread, noise, optional metal streaks
       * from fillings in the molars) and the truth labels on the same grid.
       */
      void
      acquire(CTVolume &ct, LabelVolume &truth) const;

      /**
       * The same acquisition on the grid of @p grid (its size, spacing,
       * origin and direction; its values are not used): an oblique scan of
       * the same head when the direction is not the identity. The point
       * spread acts along the grid's axes, as a scanner's does along its
       * own.
       */
      void
      acquire(const CTVolume &grid, CTVolume &ct, LabelVolume &truth) const;

      /// The largest grid grid() makes (a 0.5 mm head is 88 million).
      static constexpr std::size_t max_voxels = 400000000;

      /// The grid the acquisition uses; an Error past max_voxels.
      CTVolume
      grid() const;

      /// Landmarks a scene needs (cuts, seeds), in the patient frame.
      Vec3
      condyle(const int side) const; ///< side -1 right, +1 left
      Vec3
      gonion(const int side) const;
      Vec3
      symphysis() const;
      double
      occlusal_plane() const;

    private:
      /// Half the gap between the upper and lower teeth (mm).
      double
      teeth_gap() const
      {
        return prm.closed_mouth ? 0. : 1.5;
      }
      double
      bone_function(const Vec3 &x) const; ///< cranium and midface
      double
      mandible_function(const Vec3 &x) const;
      double
      upper_teeth_function(const Vec3 &x) const;
      double
      lower_teeth_function(const Vec3 &x) const;
      double
      brain_function(const Vec3 &x) const;

      PhantomParameters prm;
      // The mandible's landmarks after length, angle and profile.
      Vec3 gonion_right, gonion_left, body_right, body_left, symphysis_point;
      Vec3 condyle_right, condyle_left;
      /// How far the chin moved forward (+) by length and profile.
      double chin_advance = 0.;
      double chin_drop    = 0.;
    };
  } // namespace Patient
} // namespace softface

#endif

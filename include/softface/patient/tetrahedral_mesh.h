#ifndef softface_patient_tetrahedral_mesh_h
#define softface_patient_tetrahedral_mesh_h

#include <softface/patient/volume.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  namespace Patient
  {
    /**
     * The zone of the face that deforms (Mollemans et al. 2007, Sec. 3.1): an
     * axis-aligned box in the patient frame, cut further by half-spaces (a
     * point and the outward normal of the plane; the side the normal points to
     * is out).
     */
    struct RegionOfInterest
    {
      Vec3                               box_min{{-1e9, -1e9, -1e9}};
      Vec3                               box_max{{1e9, 1e9, 1e9}};
      std::vector<std::pair<Vec3, Vec3>> planes;

      bool
      contains(const Vec3 &x) const;
    };

    struct TetrahedralMeshParameters
    {
      /// Largest circumradius of a tetrahedron (mm); 0: chosen from the
      /// target number of tetrahedra and the soft tissue's volume.
      double       cell_size           = 0.;
      unsigned int target_n_tetrahedra = 100000;
      double       facet_distance      = 1.;  ///< mm, surface accuracy
      double       facet_angle         = 30.; ///< degrees, lower bound
      double       radius_edge_ratio   = 3.;
      double       sliver_bound = 12.; ///< degrees, optimisation's target
      /// Wall-clock seconds after which CGAL's sliver perturbation or
      /// exudation ends the run with an error (0: no limit). A safety stop
      /// only: the mesh never depends on it.
      double optimisation_safety_seconds = 600.;
      /// Mesh the interfaces between tissues (skin, fat, muscle) too; else
      /// the soft tissue is one domain and each cell takes the tissue at
      /// its centroid (better cells where a layer is thinner than a cell).
      bool         conforming_interfaces = false;
      unsigned int seed                  = 1; ///< CGAL's random numbers
    };

    /// Boundary ids of a patient mesh.
    constexpr unsigned int skin_boundary_id = 1;
    constexpr unsigned int cut_boundary_id  = 2;
    /// Bone contact within an osteotomy's detached margin: free.
    constexpr unsigned int detached_boundary_id = 3;
    /// Any other surface of the soft tissue (internal soft tissue beyond
    /// it, or a face that cuts a corner of the segmentation): free.
    constexpr unsigned int other_boundary_id      = 4;
    constexpr unsigned int first_bone_boundary_id = 100; ///< + segment

    struct TetrahedralMesh
    {
      std::vector<Vec3>                        points;
      std::vector<std::array<unsigned int, 4>> cells; ///< positively oriented
      std::vector<std::uint8_t>                material_ids;
      std::vector<std::array<unsigned int, 3>> boundary_faces;
      std::vector<unsigned int>                boundary_ids;
      /// How CGAL's sliver perturbation and exudation ended: "bound
      /// reached" (every dihedral angle at least the sliver bound) or "no
      /// further improvement".
      std::string perturbation_outcome, exudation_outcome;

      struct Quality
      {
        double volume             = 0.; ///< mm^3
        double min_dihedral_angle = 0.; ///< degrees
        double max_dihedral_angle = 0.;
        double worst_radius_ratio = 0.; ///< 3 inradius / circumradius
        double mean_radius_ratio  = 0.;
        double smallest_volume    = 0.; ///< mm^3
      };
      Quality
      quality() const;

      /// VTK XML (tetrahedra with MaterialID, boundary triangles with
      /// their ids in the same cell array), which Scene reads back.
      void
      write_vtu(const std::string &filename) const;
      /// gmsh 2.2 ASCII with physical ids.
      void
      write_msh(const std::string &filename) const;
    };

    /**
     * The tetrahedral soft-tissue mesh (Amira in the paper; here CGAL Mesh_3
     * from the labelled image, then perturbation and exudation of slivers):
     * every voxel of @p labels whose label is one of @p tissue_labels and
     * that lies in @p roi, with the tissue label as material id (the
     * label at the cell's centroid unless the interfaces are conforming). A
     * boundary face gets the id of what lies beyond it, probed along its
     * outward normal within two voxels: air (skin_boundary_id), the end of the
     * region of interest (cut_boundary_id), bone of segment s
     * (first_bone_boundary_id + s, where @p parts holds s + 1 on the bone of
     * segment s; nearest part within one voxel), bone near a cut
     * (detached_flag in @p parts: detached_boundary_id), or anything else,
     * including tissue all the way (other_boundary_id).
     */
    TetrahedralMesh
    make_tetrahedral_mesh(const LabelVolume               &labels,
                          const std::vector<std::uint8_t> &tissue_labels,
                          const std::uint8_t               bone_label,
                          const LabelVolume               &parts,
                          const RegionOfInterest          &roi,
                          const TetrahedralMeshParameters &parameters);
  } // namespace Patient
} // namespace softface

#endif

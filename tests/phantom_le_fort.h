#ifndef softface_tests_phantom_le_fort_h
#define softface_tests_phantom_le_fort_h

// The mesh case of the patient tests: the phantom's skull split by a Le Fort
// I cut into the cranium and the maxilla (the mandible is a part of its own),
// and the soft tissue in the region of interest of prm/patient.prm meshed
// with about 15000 tetrahedra.

#include <softface/patient/osteotomy.h>
#include <softface/patient/tetrahedral_mesh.h>

#include <vector>

namespace softface_tests
{
  struct PhantomLeFort
  {
    softface::Patient::OsteotomyParameters       osteotomy;
    std::vector<softface::Patient::SegmentSeed>  segments;
    softface::Patient::RegionOfInterest          roi;
    softface::Patient::TetrahedralMeshParameters parameters;

    /// The mesh of the soft tissue of @p labels.
    softface::Patient::TetrahedralMesh
    mesh(const softface::Patient::LabelVolume &labels) const
    {
      using namespace softface::Patient;
      return make_tetrahedral_mesh(
        labels,
        {skin_tissue, fat_tissue, muscle_tissue},
        bone_tissue,
        split_bone(labels, bone_tissue, osteotomy, segments),
        roi,
        parameters);
    }
  };

  inline PhantomLeFort
  phantom_le_fort()
  {
    PhantomLeFort          c;
    softface::Patient::Cut le_fort;
    le_fort.name                     = "le fort I";
    le_fort.point                    = {{0., 0., 0.}};
    le_fort.normal                   = {{0., 0., 1.}};
    le_fort.box_min                  = {{-80., -110., -8.}};
    le_fort.box_max                  = {{80., 0., 8.}};
    c.osteotomy.cuts                 = {le_fort};
    c.segments                       = {{"cranium", {{0., -40., 30.}}},
                                        {"maxilla", {{0., -66., -8.}}},
                                        {"mandible", {{-15., -58., -42.}}}};
    c.roi.box_min                    = {{-85., -130., -100.}};
    c.roi.box_max                    = {{85., 25., 35.}};
    c.parameters.target_n_tetrahedra = 15000;
    return c;
  }
} // namespace softface_tests

#endif

// The tetrahedral soft-tissue mesh of a patient (Mollemans et al. 2007,
// Sec. 3.1-3.3): the phantom at 2 mm voxels, segmented, its skull split by a Le
// Fort I cut into the cranium and the maxilla (the mandible is a part of its
// own), and the soft tissue of a region of interest meshed by CGAL Mesh_3. The
// mesh's volume equals the segmented soft tissue's within 2%, no cell is
// inverted, its smallest dihedral angle is at least 5 degrees, every bone part
// touches the mesh (it has join points), and the mesh written as .vtu and .msh
// reads back through the Scene's readers with the same cells and volume.

#include <softface/io/mesh_reader.h>
#include <softface/patient/osteotomy.h>
#include <softface/patient/phantom.h>
#include <softface/patient/segmentation.h>
#include <softface/patient/tetrahedral_mesh.h>

#include "phantom_le_fort.h"
#include "tests.h"

using namespace softface;
using namespace softface::Patient;

SOFTFACE_TEST(patient_mesh)
{
  PhantomParameters p;
  p.voxel_size = 2.;
  CTVolume    ct;
  LabelVolume truth;
  Phantom(p).acquire(ct, truth);
  const LabelVolume labels =
    segment(ct, SegmentationParameters(), "phantom").labels;

  const auto            le_fort  = softface_tests::phantom_le_fort();
  const auto           &segments = le_fort.segments;
  const auto           &roi      = le_fort.roi;
  const TetrahedralMesh mesh     = le_fort.mesh(labels);

  std::size_t n_soft = 0;
  for (std::size_t k = 0; k < labels.size[2]; ++k)
    for (std::size_t j = 0; j < labels.size[1]; ++j)
      for (std::size_t i = 0; i < labels.size[0]; ++i)
        {
          const auto l = labels(i, j, k);
          n_soft +=
            (l == skin_tissue || l == fat_tissue || l == muscle_tissue) &&
            roi.contains(labels.point(i, j, k));
        }
  const double soft_volume = n_soft * labels.voxel_volume();
  const auto   q           = mesh.quality();
  // Mesh_3 does not make the same mesh twice: ranges, not values.
  softface_tests::check_within(
    "tetrahedra", mesh.cells.size(), 10000, 22500, 9);
  softface_tests::check_within("(mesh volume - segmented soft tissue) / "
                               "segmented",
                               (q.volume - soft_volume) / soft_volume,
                               -0.02,
                               0.02);
  softface_tests::check_within("smallest cell volume (mm^3)",
                               q.smallest_volume,
                               1e-12,
                               1e9);
  softface_tests::check_within("smallest dihedral angle (degrees)",
                               q.min_dihedral_angle,
                               5.,
                               90.);

  std::vector<unsigned int> faces_of_part(segments.size(), 0);
  for (const auto id : mesh.boundary_ids)
    if (id >= first_bone_boundary_id &&
        id < first_bone_boundary_id + segments.size())
      ++faces_of_part[id - first_bone_boundary_id];
  for (unsigned int s = 0; s < segments.size(); ++s)
    softface_tests::check_within(
      segments[s].name + ": bone contact faces", faces_of_part[s], 10, 1e9, 9);

  for (const std::string file : {"patient_mesh.vtu", "patient_mesh.msh"})
    {
      if (file.find(".vtu") != std::string::npos)
        mesh.write_vtu(file);
      else
        mesh.write_msh(file);
      Triangulation<3> triangulation;
      Mesh::read_file(file, triangulation);
      softface_tests::check_equal(file + ": cells read back - cells written",
                                  triangulation.n_active_cells() -
                                    static_cast<long long>(mesh.cells.size()),
                                  0);
      double volume = 0.;
      for (const auto &cell : triangulation.active_cell_iterators())
        volume += cell->measure();
      softface_tests::check_below(file + ": |volume read back - volume| / "
                                         "volume",
                                  std::abs(volume - q.volume) / q.volume,
                                  1e-6);
    }
}

#ifndef softface_simulator_output_h
#define softface_simulator_output_h

#include <deal.II/base/mpi.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/simulator/report.h>

#include <string>
#include <vector>

namespace softface
{
  class DistributedLayout;

  /**
   * The fields a run writes: one VTU for ParaView with every model's
   * displacement and the scene's labels, and per-vertex displacement CSVs.
   */
  namespace Output
  {
    /// "mass tensor" -> "mass_tensor", "linear fem, bone rotation angle 5"
    /// -> "linear_fem_bone_rotation_angle_5"
    std::string
    file_name_of(const std::string &model);

    /**
     * One VTU with every successful model's displacement
     * ("displacement_<model>"), the join/free flag (1 = join) and the segment
     * id (-1 = free) per vertex, and the material id per cell. A .pvtu of
     * the same stem and its pieces, left by a run on several ranks, are
     * removed.
     */
    void
    write_vtu(const Scene                         &scene,
              const std::vector<Report::ModelRun> &runs,
              const std::string                   &filename);

    /**
     * The same fields on the ranks of @p communicator from the scene each
     * holds, where no distributed layout was made (a partition for output
     * alone costs seconds at millions of cells): each rank writes the
     * piece <stem>.<rank>.vtu of a contiguous range of the scene's cells
     * (the 'cell order' partition) and rank 0 the record <stem>.pvtu.
     * Collective; every rank must hold the cells (Scene::has_cells()).
     */
    void
    write_pvtu(const Scene                         &scene,
               const std::vector<Report::ModelRun> &runs,
               const std::string                   &stem,
               const MPI_Comm                       communicator);

    /**
     * The same fields on the ranks of @p layout (issue 20): each rank
     * writes the piece <stem>.<rank>.vtu of the cells it owns and rank 0 the
     * record <stem>.pvtu that ParaView opens as one mesh (and removes a
     * <stem>.vtu left by a serial run). It reads the rank's part of the mesh
     * and the whole answers, not the scene's cells. Collective; the folder
     * of @p stem must exist on every rank.
     */
    void
    write_pvtu(const DistributedLayout             &layout,
               const std::vector<Report::ModelRun> &runs,
               const std::string                   &stem);

    /// Columns x,y,z,ux,uy,uz: one row per vertex, reference coordinates.
    void
    write_nodal_displacements(const Scene          &scene,
                              const Vector<double> &displacement,
                              const std::string    &filename);
  } // namespace Output
} // namespace softface

#endif

#ifndef softface_outputs_solution_h
#define softface_outputs_solution_h

#include <deal.II/base/mpi.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/outputs/report.h>

#include <string>
#include <vector>

namespace softface
{
  class DistributedLayout;

  /**
   * The fields of the 'solution' output (source/outputs/solution.cc): one
   * VTU for ParaView with every model's displacement and the scene's labels,
   * or its pieces on several ranks.
   */
  namespace Outputs
  {
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
     * The same fields on the ranks of @p layout: each rank
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
  } // namespace Outputs
} // namespace softface

#endif

#ifndef softface_output_h
#define softface_output_h

#include <deal.II/lac/vector.h>

#include <softface/models/interface.h>
#include <softface/core/scene.h>

#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  /**
   * What a run writes: the side-by-side table (stdout and summary.csv), the
   * VTU for ParaView and the per-vertex displacement CSV.
   */
  namespace Output
  {
    /// One row of the side-by-side table.
    struct ModelRun
    {
      std::string        model;
      Models::Statistics statistics;
      Vector<double>     displacement;
      /// Largest and mean |u - u_linear_fem| over the free vertices (mm);
      /// negative when the run has no linear fem row to compare with.
      double max_difference  = -1.;
      double mean_difference = -1.;
    };

    /// Fill every run's difference to the "linear fem" run, if there is one.
    void
    compare_to_linear_fem(const Scene &scene, std::vector<ModelRun> &runs);

    /// Largest vertex displacement |u| in mm.
    double
    max_displacement(const Scene &scene, const Vector<double> &displacement);

    /// "mass tensor" -> "mass_tensor"
    std::string
    file_name_of(const std::string &model);

    /// Columns model,n_tets,n_vertices,n_free_dofs,setup_s,solve_s,
    /// iterations,max_displacement_mm,max_diff_to_linear_fem_mm,
    /// mean_diff_to_linear_fem_mm (empty without linear fem),
    /// relative_residual, phases and details ("name=value" pairs joined by
    /// ';': each model's own figures, e.g. Newton iterations per load step).
    void
    write_summary_csv(const Scene                 &scene,
                      const std::vector<ModelRun> &runs,
                      const std::string           &filename);

    void
    print_summary_table(const Scene                 &scene,
                        const std::vector<ModelRun> &runs,
                        std::ostream                &out);

    /**
     * One VTU with every model's displacement ("displacement_<model>"), the
     * join/free flag (1 = join) and the segment id (-1 = free) per vertex.
     */
    void
    write_vtu(const Scene                 &scene,
              const std::vector<ModelRun> &runs,
              const std::string           &filename);

    /// Columns x,y,z,ux,uy,uz: one row per vertex, reference coordinates.
    void
    write_nodal_displacements(const Scene          &scene,
                              const Vector<double> &displacement,
                              const std::string    &filename);
  } // namespace Output
} // namespace softface

#endif

#ifndef softface_outputs_report_h
#define softface_outputs_report_h

#include <deal.II/base/table_handler.h>
#include <deal.II/lac/vector.h>

#include <softface/core/displacement.h>
#include <softface/core/scene.h>
#include <softface/models/interface.h>

#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  /**
   * What a run reports about its models, without asking which model ran:
   * the side-by-side table on the screen (deal.II's TableHandler), the same
   * in summary.csv with full precision and in an aligned statistics file,
   * each model's phases, figures and warnings, and every model's difference
   * to the reference model ('Output/Reference model').
   */
  namespace Report
  {
    /// One model's run of a scene.
    struct ModelRun
    {
      std::string model;
      /// The plan's name when the scene runs several (PlanningList), else
      /// empty.
      std::string planning;
      /// s, the model's response basis (0: none), on top of its setup
      double basis_time = 0.;
      /// "model" or "model, plan": names the run in tables and file names.
      std::string
      label() const
      {
        return planning.empty() ? model : model + ", " + planning;
      }
      bool               failed = false;
      std::string        error; ///< why it failed
      Models::Statistics statistics;
      Vector<double>     displacement;
      double             max_displacement = 0.; ///< mm
      /// Set by compare_to() when the reference model ran.
      bool                     compared = false;
      Displacement::Difference difference;
      double                   peak_memory_mb = 0.; ///< process, after it ran
    };

    /// Fill every successful run's difference to the run of
    /// @p reference_model with the same plan, if it ran successfully.
    void
    compare_to(const Scene           &scene,
               const std::string     &reference_model,
               std::vector<ModelRun> &runs);

    /**
     * The table of the successful runs: model, (plan, when there are
     * several,) tets, vertices, free DoFs, (setup s, basis s when a model
     * built a response basis, solve s,) iterations, max |u| and, when compared,
     * the largest and mean difference to the reference model; @p with_extras
     * adds the model's DoFs, its relative residual and the peak memory.
     */
    TableHandler
    table(const Scene                 &scene,
          const std::vector<ModelRun> &runs,
          const bool                   with_timings,
          const bool                   with_extras);

    /**
     * The table, which model it compares to, and per model its phases (with
     * timings only), figures and warnings; failed models with their error.
     * Without timings it is the same on every run: tests compare it.
     */
    void
    print(const Scene                 &scene,
          const std::vector<ModelRun> &runs,
          const std::string           &reference_model,
          const bool                   with_timings,
          std::ostream                &out);

    /**
     * One row per model, numbers in full precision. Columns: model, status
     * (ok, failed), n_tets, n_vertices, n_free_dofs, n_dofs, setup_s,
     * solve_s, iterations, relative_residual, max_displacement_mm,
     * reference_model, max_diff_to_reference_mm, mean_diff_to_reference_mm,
     * peak_memory_mb, phases and details ("name=value" joined by ';'),
     * warnings, error, plan (empty for a scene's one planning) and
     * basis_s (the response basis, 0 without).
     */
    void
    write_summary_csv(const Scene                 &scene,
                      const std::vector<ModelRun> &runs,
                      const std::string           &reference_model,
                      const std::string           &filename);

    /// The table with timings and extras, aligned, with a column legend.
    void
    write_statistics(const Scene                 &scene,
                     const std::vector<ModelRun> &runs,
                     const std::string           &filename);
  } // namespace Report
} // namespace softface

#endif

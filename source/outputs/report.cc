// What a run reports (simulator): the side-by-side table on the screen and in
// a statistics file (TableHandler), summary.csv in full precision, each
// model's phases, figures and warnings, and the comparison with the
// reference model. Nothing here asks which model ran.

#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/outputs/report.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace softface
{
  namespace Report
  {
    namespace
    {

      // The shortest text that reads back as the same double.
      std::string
      full(const double value)
      {
        char       buffer[32];
        const auto end = std::to_chars(buffer, buffer + 32, value).ptr;
        return std::string(buffer, end);
      }

      std::string
      joined(const std::vector<std::string> &items, const std::string &by)
      {
        std::string text;
        for (const auto &item : items)
          text += (text.empty() ? "" : by) + item;
        return text;
      }
    } // namespace

    void
    compare_to(const Scene           &scene,
               const std::string     &reference_model,
               std::vector<ModelRun> &runs)
    {
      std::map<std::string, const ModelRun *> reference_of_plan;
      for (const ModelRun &run : runs)
        if (run.model == reference_model && !run.failed)
          reference_of_plan[run.planning] = &run;
      for (ModelRun &run : runs)
        {
          const auto      found = reference_of_plan.find(run.planning);
          const ModelRun *reference =
            found == reference_of_plan.end() ? nullptr : found->second;
          run.compared = (reference != nullptr && !run.failed);
          if (run.compared)
            run.difference =
              Displacement::free_vertex_difference(scene,
                                                   run.displacement,
                                                   reference->displacement);
        }
    }

    TableHandler
    table(const Scene                 &scene,
          const std::vector<ModelRun> &runs,
          const bool                   with_timings,
          const bool                   with_extras)
    {
      TableHandler table;
      bool         any = false, compared = false, plans = false, bases = false;
      for (const ModelRun &run : runs)
        {
          plans |= !run.planning.empty();
          bases |= run.basis_time > 0.;
        }
      for (const ModelRun &run : runs)
        {
          if (run.failed)
            continue;
          any = true;
          compared |= run.compared;
          const auto &s = run.statistics;
          table.add_value("model", run.model);
          if (plans)
            table.add_value("plan", run.planning);
          table.add_value("tets", scene.n_cells());
          table.add_value("vertices", scene.n_vertices());
          table.add_value("free DoFs", scene.n_free_dofs());
          if (with_extras)
            table.add_value("DoFs", s.n_dofs > 0 ? s.n_dofs : scene.n_dofs());
          if (with_timings)
            {
              table.add_value("setup s", s.setup_time);
              if (bases)
                table.add_value("basis s", run.basis_time);
              table.add_value("solve s", s.solve_time);
            }
          table.add_value("iters", s.iterations);
          table.add_value("max |u| mm", run.max_displacement);
          if (run.compared)
            {
              table.add_value("|u - u_ref| max", run.difference.max);
              table.add_value("mean", run.difference.mean);
            }
          if (with_extras)
            {
              table.add_value("relative residual", s.residual);
              table.add_value("peak memory MB", run.peak_memory_mb);
            }
        }
      if (!any)
        return table;
      // (Setting a column's precision creates the column if it is missing.)
      if (with_timings)
        for (const std::string column : {"setup s", "solve s"})
          table.set_precision(column, 3);
      // A combination takes well under a millisecond.
      if (with_timings && bases)
        {
          table.set_precision("basis s", 3);
          table.set_precision("solve s", 5);
        }
      table.set_precision("max |u| mm", 4);
      if (compared)
        for (const std::string column : {"|u - u_ref| max", "mean"})
          table.set_precision(column, 4);
      if (with_extras)
        {
          table.set_precision("relative residual", 2);
          table.set_scientific("relative residual", true);
          table.set_precision("peak memory MB", 0);
        }
      return table;
    }

    void
    print(const Scene                 &scene,
          const std::vector<ModelRun> &runs,
          const std::string           &reference_model,
          const bool                   with_timings,
          std::ostream                &out)
    {
      const auto flags    = out.flags();
      bool       any      = false;
      bool       compared = false;
      for (const ModelRun &run : runs)
        {
          any |= !run.failed;
          compared |= run.compared;
        }
      if (any)
        table(scene, runs, with_timings, false)
          .write_text(out, TableHandler::table_with_headers);
      out << (compared ?
                "u_ref: the displacement of '" + reference_model +
                  "' (Output/Reference model), over the free vertices" :
                "no comparison: the reference model '" + reference_model +
                  "' did not run")
          << "\n\n";
      for (const ModelRun &run : runs)
        {
          if (run.failed)
            {
              // Models' own errors start with the model's name.
              out << (run.error.rfind(run.model + ":", 0) == 0 &&
                          run.planning.empty() ?
                        "failed: " :
                        run.label() + " failed: ")
                  << run.error << '\n';
              continue;
            }
          // A model's later plans repeat its setup phases: summary.csv has
          // them all.
          const bool later_plan = &run != &runs.front() &&
                                  (&run - 1)->model == run.model &&
                                  !run.planning.empty();
          if (with_timings && !later_plan)
            {
              out << run.label() << " phases (s):";
              for (const auto &[name, seconds] : run.statistics.phases)
                out << "  " << name << ' ' << std::setprecision(3) << seconds;
              out << '\n';
            }
          out << run.label() << " details:";
          out << "  relative residual " << std::setprecision(2)
              << std::scientific << run.statistics.residual;
          out.flags(flags);
          for (const auto &detail : run.statistics.details)
            if (with_timings || !detail.depends_on_timing)
              out << "  " << detail.name << ' ' << detail.formatted();
          out << '\n';
          for (const auto &warning : run.statistics.warnings)
            out << run.label() << " warning: " << warning << '\n';
        }
      out.flags(flags);
    }

    void
    write_summary_csv(const Scene                 &scene,
                      const std::vector<ModelRun> &runs,
                      const std::string           &reference_model,
                      const std::string           &filename)
    {
      std::ofstream out = open_output_file(filename);
      out << "model,status,n_tets,n_vertices,n_free_dofs,n_dofs,setup_s,"
             "solve_s,iterations,relative_residual,max_displacement_mm,"
             "reference_model,max_diff_to_reference_mm,"
             "mean_diff_to_reference_mm,peak_memory_mb,phases,details,"
             "warnings,error,plan,basis_s\n";
      for (const ModelRun &run : runs)
        {
          const auto &s = run.statistics;
          out << csv_field(run.model) << ',' << (run.failed ? "failed" : "ok")
              << ',' << scene.n_cells() << ',' << scene.n_vertices() << ','
              << scene.n_free_dofs() << ','
              << (s.n_dofs > 0 ? s.n_dofs : scene.n_dofs()) << ',';
          if (run.failed)
            out << ",,,,,,,,";
          else
            {
              out << full(s.setup_time) << ',' << full(s.solve_time) << ','
                  << s.iterations << ',' << full(s.residual) << ','
                  << full(run.max_displacement) << ',';
              if (run.compared)
                out << csv_field(reference_model) << ','
                    << full(run.difference.max) << ','
                    << full(run.difference.mean);
              else
                out << ",,";
              out << ',';
            }
          out << full(run.peak_memory_mb) << ',';
          std::vector<std::string> phases, details;
          for (const auto &[name, seconds] : s.phases)
            phases.push_back(name + '=' + full(seconds));
          for (const auto &detail : s.details)
            details.push_back(detail.name + '=' + detail.formatted(0));
          out << csv_field(joined(phases, ";")) << ','
              << csv_field(joined(details, ";")) << ','
              << csv_field(joined(s.warnings, " | ")) << ','
              << csv_field(run.error) << ',' << csv_field(run.planning) << ','
              << full(run.basis_time) << '\n';
        }
    }

    void
    write_statistics(const Scene                 &scene,
                     const std::vector<ModelRun> &runs,
                     const std::string           &filename)
    {
      std::ofstream out = open_output_file(filename);
      for (const ModelRun &run : runs)
        if (!run.failed)
          {
            table(scene, runs, true, true)
              .write_text(out,
                          TableHandler::table_with_separate_column_description);
            return;
          }
    }
  } // namespace Report
} // namespace softface

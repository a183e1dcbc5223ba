#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/numerics/data_out.h>

#include <softface/core/error.h>
#include <softface/simulator/output.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>

namespace softface
{
  namespace Output
  {
    double
    max_displacement(const Scene &scene, const Vector<double> &u)
    {
      double max_norm = 0.;
      for (const auto &dofs : scene.vertex_dofs())
        if (dofs[0] != numbers::invalid_dof_index)
          max_norm = std::max(max_norm,
                              std::sqrt(u[dofs[0]] * u[dofs[0]] +
                                        u[dofs[1]] * u[dofs[1]] +
                                        u[dofs[2]] * u[dofs[2]]));
      return max_norm;
    }

    void
    compare_to_linear_fem(const Scene &scene, std::vector<ModelRun> &runs)
    {
      const auto reference =
        std::find_if(runs.begin(), runs.end(), [](const ModelRun &run) {
          return run.model == "linear fem";
        });
      if (reference == runs.end())
        return;
      for (ModelRun &run : runs)
        {
          double       max = 0., sum = 0.;
          unsigned int n = 0;
          for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
            {
              const auto &dofs = scene.vertex_dofs()[v];
              if (dofs[0] == numbers::invalid_dof_index ||
                  scene.vertex_segment()[v] != numbers::invalid_unsigned_int)
                continue;
              double d = 0.;
              for (const auto dof : dofs)
                d +=
                  std::pow(run.displacement[dof] - reference->displacement[dof],
                           2);
              d   = std::sqrt(d);
              max = std::max(max, d);
              sum += d;
              ++n;
            }
          run.max_difference  = max;
          run.mean_difference = n ? sum / n : 0.;
        }
    }

    std::string
    file_name_of(const std::string &model)
    {
      std::string name = model;
      std::replace(name.begin(), name.end(), ' ', '_');
      return name;
    }

    namespace
    {
      std::ofstream
      open(const std::string &filename)
      {
        std::ofstream out(filename);
        if (!out)
          throw Error("Cannot write '" + filename + "'.");
        return out;
      }
    } // namespace

    void
    write_summary_csv(const Scene                 &scene,
                      const std::vector<ModelRun> &runs,
                      const std::string           &filename)
    {
      std::ofstream out = open(filename);
      out << "model,n_tets,n_vertices,n_free_dofs,setup_s,solve_s,iterations,"
             "max_displacement_mm,max_diff_to_linear_fem_mm,"
             "mean_diff_to_linear_fem_mm,relative_residual,phases,details\n";
      for (const ModelRun &run : runs)
        {
          out << run.model << ',' << scene.triangulation.n_active_cells() << ','
              << scene.n_vertices() << ',' << scene.n_free_dofs() << ','
              << std::setprecision(6) << run.statistics.setup_time << ','
              << run.statistics.solve_time << ',' << run.statistics.iterations
              << ',' << std::setprecision(10)
              << max_displacement(scene, run.displacement) << ','
              << (run.max_difference >= 0 ? std::to_string(run.max_difference) :
                                            "")
              << ','
              << (run.mean_difference >= 0 ?
                    std::to_string(run.mean_difference) :
                    "")
              << ',' << std::setprecision(3) << run.statistics.residual << ',';
          // Phases and details as "name=value" pairs separated by ';'.
          for (unsigned int i = 0; i < run.statistics.phases.size(); ++i)
            out << (i ? ";" : "") << run.statistics.phases[i].first << '='
                << std::setprecision(4) << run.statistics.phases[i].second;
          out << ',';
          for (unsigned int i = 0; i < run.statistics.details.size(); ++i)
            out << (i ? ";" : "") << run.statistics.details[i].first << '='
                << run.statistics.details[i].second;
          out << '\n';
        }
    }

    void
    print_summary_table(const Scene                 &scene,
                        const std::vector<ModelRun> &runs,
                        std::ostream                &out)
    {
      const auto flags = out.flags();
      out << '\n'
          << std::left << std::setw(14) << "model" << std::right
          << std::setw(10) << "tets" << std::setw(10) << "vertices"
          << std::setw(11) << "free DoFs" << std::setw(10) << "setup s"
          << std::setw(10) << "solve s" << std::setw(8) << "iters"
          << std::setw(14) << "max |u| mm" << std::setw(22)
          << "|u - u_linfem| max" << std::setw(8) << "mean" << '\n'
          << std::string(117, '-') << '\n';
      for (const ModelRun &run : runs)
        {
          out << std::left << std::setw(14) << run.model << std::right
              << std::setw(10) << scene.triangulation.n_active_cells()
              << std::setw(10) << scene.n_vertices() << std::setw(11)
              << scene.n_free_dofs() << std::fixed << std::setprecision(3)
              << std::setw(10) << run.statistics.setup_time << std::setw(10)
              << run.statistics.solve_time << std::setw(8)
              << run.statistics.iterations << std::setprecision(4)
              << std::setw(14) << max_displacement(scene, run.displacement);
          if (run.max_difference >= 0)
            out << std::setw(22) << run.max_difference << std::setw(8)
                << run.mean_difference;
          out << '\n';
        }
      out << '\n';
      for (const ModelRun &run : runs)
        {
          out << run.model << " phases:";
          for (const auto &[name, seconds] : run.statistics.phases)
            out << "  " << name << ' ' << std::setprecision(3) << seconds
                << " s";
          out << "  (relative residual " << std::scientific
              << std::setprecision(1) << run.statistics.residual << ")\n"
              << std::fixed;
          if (!run.statistics.details.empty())
            {
              out << run.model << " details:";
              for (const auto &[name, value] : run.statistics.details)
                out << "  " << name << ' ' << value;
              out << '\n';
            }
        }
      out.flags(flags);
    }

    void
    write_vtu(const Scene                 &scene,
              const std::vector<ModelRun> &runs,
              const std::string           &filename)
    {
      // Per-vertex flags live on a scalar P1 layout beside the vector one.
      DoFHandler<3> scalar_dofs(scene.triangulation);
      scalar_dofs.distribute_dofs(FE_SimplexP<3>(1));
      Vector<double> join_flag(scalar_dofs.n_dofs());
      Vector<double> segment_id(scalar_dofs.n_dofs());
      for (const auto &cell : scalar_dofs.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          {
            const unsigned int s =
              scene.vertex_segment()[cell->vertex_index(v)];
            const auto dof  = cell->vertex_dof_index(v, 0);
            join_flag[dof]  = (s == numbers::invalid_unsigned_int) ? 0. : 1.;
            segment_id[dof] = (s == numbers::invalid_unsigned_int) ? -1. : s;
          }

      DataOut<3> data_out;
      data_out.attach_triangulation(scene.triangulation);
      const std::vector<
        DataComponentInterpretation::DataComponentInterpretation>
        vector(3, DataComponentInterpretation::component_is_part_of_vector);
      for (const ModelRun &run : runs)
        data_out.add_data_vector(
          scene.dof_handler,
          run.displacement,
          std::vector<std::string>(3,
                                   "displacement_" + file_name_of(run.model)),
          vector);
      data_out.add_data_vector(scalar_dofs, join_flag, "join_point");
      data_out.add_data_vector(scalar_dofs, segment_id, "segment_id");
      Vector<float> material(scene.triangulation.n_active_cells());
      for (const auto &cell : scene.triangulation.active_cell_iterators())
        material[cell->active_cell_index()] = cell->material_id();
      data_out.add_data_vector(material, "material_id");
      data_out.build_patches(scene.mapping);
      // zlib at its strongest spends seconds on large meshes for little gain.
      DataOutBase::VtkFlags flags;
      flags.compression_level = DataOutBase::VtkFlags::best_speed;
      data_out.set_flags(flags);

      std::ofstream out = open(filename);
      data_out.write_vtu(out);
    }

    void
    write_nodal_displacements(const Scene          &scene,
                              const Vector<double> &u,
                              const std::string    &filename)
    {
      std::ofstream out = open(filename);
      out << "x,y,z,ux,uy,uz\n" << std::setprecision(12);
      const auto &vertices = scene.triangulation.get_vertices();
      for (unsigned int v = 0; v < vertices.size(); ++v)
        {
          const auto &dofs = scene.vertex_dofs()[v];
          if (dofs[0] == numbers::invalid_dof_index)
            continue;
          out << vertices[v][0] << ',' << vertices[v][1] << ','
              << vertices[v][2] << ',' << u[dofs[0]] << ',' << u[dofs[1]] << ','
              << u[dofs[2]] << '\n';
        }
    }
  } // namespace Output
} // namespace softface

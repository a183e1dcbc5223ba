// The fields a run writes (simulator): solution.vtu with every model's
// displacement and the scene's labels for ParaView, and per-vertex CSVs.

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/numerics/data_out.h>

#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/simulator/output.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>

namespace softface
{
  namespace Output
  {
    std::string
    file_name_of(const std::string &model)
    {
      // Letters, digits, '.', '-' and '+' stay; any run of other characters
      // (spaces, the comma before a plan's name) becomes one '_'.
      std::string name;
      for (const char c : model)
        if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' ||
            c == '-' || c == '+')
          name += c;
        else if (name.empty() || name.back() != '_')
          name += '_';
      return name;
    }

    void
    write_vtu(const Scene                         &scene,
              const std::vector<Report::ModelRun> &runs,
              const std::string                   &filename)
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
      for (const Report::ModelRun &run : runs)
        if (!run.failed)
          data_out.add_data_vector(scene.dof_handler,
                                   run.displacement,
                                   std::vector<std::string>(3,
                                                            "displacement_" +
                                                              file_name_of(
                                                                run.label())),
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

      std::ofstream out = open_output_file(filename);
      data_out.write_vtu(out);
    }

    void
    write_nodal_displacements(const Scene          &scene,
                              const Vector<double> &u,
                              const std::string    &filename)
    {
      std::ofstream out = open_output_file(filename);
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

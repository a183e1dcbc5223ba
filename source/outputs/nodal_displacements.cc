// The 'nodal displacements' output: displacements_<model>.csv per successful
// run, one row per vertex ('Output/Write nodal displacements').

#include <softface/io/output_file.h>
#include <softface/outputs/interface.h>

#include <fstream>
#include <iomanip>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      class NodalDisplacements : public Interface
      {
      public:
        static void
        declare_parameters(ParameterHandler &prm)
        {
          prm.declare_entry("Write nodal displacements",
                            "false",
                            Patterns::Bool(),
                            "Write displacements_<model>.csv with columns "
                            "x,y,z,ux,uy,uz (mm), one row per vertex in "
                            "reference coordinates.");
        }

        void
        parse_parameters(ParameterHandler &prm, const std::string &) override
        {
          asked = prm.get_bool("Write nodal displacements");
        }

        bool
        requested() const override
        {
          return asked;
        }

        void
        write(const Run &run, std::ostream &) override
        {
          if (!run.writes_outputs)
            return;
          for (const auto &model_run : run.runs)
            if (!model_run.failed)
              write_csv(run.scene,
                        model_run.displacement,
                        run.directory + "/displacements_" +
                          file_name_of(model_run.label()) + ".csv");
        }

        std::string
        files(const Run &) const override
        {
          return "displacements_*.csv";
        }

      private:
        /// Columns x,y,z,ux,uy,uz: one row per vertex, reference
        /// coordinates.
        static void
        write_csv(const Scene          &scene,
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
                  << vertices[v][2] << ',' << u[dofs[0]] << ',' << u[dofs[1]]
                  << ',' << u[dofs[2]] << '\n';
            }
        }

        bool asked = false;
      };
    } // namespace

    SOFTFACE_REGISTER_OUTPUT(NodalDisplacements,
                             "nodal displacements",
                             "displacements_<model>.csv ('Write nodal "
                             "displacements'): x,y,z,ux,uy,uz per vertex")
  } // namespace Outputs
} // namespace softface

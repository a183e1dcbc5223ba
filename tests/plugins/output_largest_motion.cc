// An output is one file: this one, registered in one line and asked for by
// 'Output/Write largest motion' (output_largest_motion.prm), writes
// largest_motion.csv: per model, the free vertex that moves most and by how
// much. It keeps each answer as the models give it (add_answer) and writes
// at the end (write), as the outputs in source/outputs/ do. The test reads
// the file back: linear FEM and the mass tensor model, which converges to
// the same equations, must name the same vertex and agree on its motion to
// the model's stop threshold, and no free vertex may move more than the
// largest motion of all (the planning's, at the join points).

#include <softface/io/output_file.h>
#include <softface/outputs/interface.h>

#include "../run_scene.h"

#include <cmath>
#include <fstream>
#include <iomanip>

namespace
{
  using namespace dealii;

  class LargestMotion : public softface::Outputs::Interface
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Write largest motion",
                        "false",
                        Patterns::Bool(),
                        "Write largest_motion.csv: per model, the free "
                        "vertex that moves most (mm).");
    }

    void
    parse_parameters(ParameterHandler &prm, const std::string &) override
    {
      asked = prm.get_bool("Write largest motion");
    }

    bool
    requested() const override
    {
      return asked;
    }

    void
    add_answer(const softface::Outputs::Run     &run,
               const softface::Report::ModelRun &model_run,
               softface::Models::Interface &,
               bool) override
    {
      const softface::Scene &scene = run.scene;
      const auto            &u     = model_run.displacement;
      Row                    row{model_run.label(), 0, 0.};
      for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
        {
          const auto &dofs = scene.vertex_dofs()[v];
          if (dofs[0] == numbers::invalid_dof_index ||
              scene.vertex_segment()[v] != numbers::invalid_unsigned_int)
            continue;
          const double motion =
            std::sqrt(u[dofs[0]] * u[dofs[0]] + u[dofs[1]] * u[dofs[1]] +
                      u[dofs[2]] * u[dofs[2]]);
          if (motion > row.motion)
            row = {model_run.label(), v, motion};
        }
      rows.push_back(row);
    }

    void
    write(const softface::Outputs::Run &run, std::ostream &) override
    {
      if (!run.writes_outputs)
        return;
      auto csv =
        softface::open_output_file(run.directory + "/largest_motion.csv");
      csv << "model,vertex,x,y,z,motion_mm\n" << std::setprecision(12);
      for (const Row &row : rows)
        {
          const Point<3> &x =
            run.scene.triangulation.get_vertices()[row.vertex];
          csv << row.model << ',' << row.vertex << ',' << x[0] << ',' << x[1]
              << ',' << x[2] << ',' << row.motion << '\n';
        }
    }

    std::string
    files(const softface::Outputs::Run &) const override
    {
      return "largest_motion.csv";
    }

  private:
    struct Row
    {
      std::string  model;
      unsigned int vertex;
      double       motion;
    };
    bool             asked = false;
    std::vector<Row> rows;
  };

  SOFTFACE_REGISTER_OUTPUT(LargestMotion,
                           "largest motion",
                           "largest_motion.csv: the free vertex that moves "
                           "most, per model (test)")
} // namespace

SOFTFACE_TEST(output_largest_motion)
{
  softface::Simulator simulator;
  const int           exit_code =
    softface_tests::run_scene(simulator,
                              softface_tests::source_file(
                                "plugins/output_largest_motion.prm"));
  softface_tests::check_equal("exit code", exit_code, 0);

  std::ifstream in("output_largest_motion_output/largest_motion.csv");
  std::string   line;
  std::getline(in, line);
  deallog << "largest_motion.csv: " << line << std::endl;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line))
    rows.push_back(Utilities::split_string_list(line, ','));
  softface_tests::check_equal("rows", rows.size(), 2);
  for (const auto &row : rows)
    deallog << row[0] << ": vertex " << row[1] << " at ("
            << softface_tests::rounded(std::stod(row[2])) << ", "
            << softface_tests::rounded(std::stod(row[3])) << ", "
            << softface_tests::rounded(std::stod(row[4])) << ") moves "
            << softface_tests::rounded(std::stod(row[5]), 4) << " mm"
            << std::endl;
  softface_tests::check_equal("the models name the same vertex",
                              std::stoi(rows[0][1]) == std::stoi(rows[1][1]),
                              1);
  softface_tests::check_below("|mass tensor - linear fem| at it (mm)",
                              std::abs(std::stod(rows[1][5]) -
                                       std::stod(rows[0][5])),
                              1e-4);
  for (unsigned int r = 0; r < 2; ++r)
    softface_tests::check_below(rows[r][0] +
                                  ": largest free motion / largest motion",
                                std::stod(rows[r][5]) /
                                  simulator.runs()[r].max_displacement,
                                1.);
}

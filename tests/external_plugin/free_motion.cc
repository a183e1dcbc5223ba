// An output written outside softface's tree: 'Output/Write free motion'
// writes free_motion.csv, per model the mean and the largest motion of the
// free vertices (mm). Built against the installed softface
// (CMakeLists.txt here) and loaded by a scene that names its library in
// 'Additional shared libraries' (free_motion.prm).

#include <softface/io/output_file.h>
#include <softface/outputs/interface.h>

#include <algorithm>
#include <cmath>
#include <iomanip>

namespace
{
  using namespace dealii;

  class FreeMotion : public softface::Outputs::Interface
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Write free motion",
                        "false",
                        Patterns::Bool(),
                        "Write free_motion.csv: per model, the mean and the "
                        "largest motion of the free vertices (mm).");
    }

    void
    parse_parameters(ParameterHandler &prm, const std::string &) override
    {
      asked = prm.get_bool("Write free motion");
    }

    bool
    requested() const override
    {
      return asked;
    }

    void
    write(const softface::Outputs::Run &run, std::ostream &) override
    {
      if (!run.writes_outputs)
        return;
      auto csv = softface::open_output_file(run.directory + "/free_motion.csv");
      csv << "model,mean_mm,max_mm\n" << std::setprecision(12);
      const softface::Scene &scene = run.scene;
      for (const auto &model_run : run.runs)
        {
          if (model_run.failed)
            continue;
          const auto  &u   = model_run.displacement;
          double       sum = 0., largest = 0.;
          unsigned int n = 0;
          for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
            {
              const auto &dofs = scene.vertex_dofs()[v];
              if (dofs[0] == numbers::invalid_dof_index ||
                  scene.vertex_segment()[v] != numbers::invalid_unsigned_int)
                continue;
              const double motion =
                std::sqrt(u[dofs[0]] * u[dofs[0]] + u[dofs[1]] * u[dofs[1]] +
                          u[dofs[2]] * u[dofs[2]]);
              sum += motion;
              largest = std::max(largest, motion);
              ++n;
            }
          csv << model_run.label() << ',' << sum / std::max(n, 1u) << ','
              << largest << '\n';
        }
    }

    std::string
    files(const softface::Outputs::Run &) const override
    {
      return "free_motion.csv";
    }

  private:
    bool asked = false;
  };

  SOFTFACE_REGISTER_OUTPUT(FreeMotion,
                           "free motion",
                           "free_motion.csv: the mean and largest motion of "
                           "the free vertices, per model")
} // namespace

// No result depends on the order of Models/Models: the scene of
// run_multi_model.prm with its five models listed forward and in reverse
// gives every model the same answer, bit for bit, and the same figures,
// among them the mass tensor model's precision against linear FEM's answer
// (which it can only measure when linear FEM has run), because each model
// runs after the models whose answers it takes. The table lists the models
// as the file does.

#include "run_scene.h"

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace
{
  struct Answer
  {
    dealii::Vector<double> displacement;
    std::string            figures;
  };

  std::map<std::string, Answer>
  run_with_models(const std::string &models, const std::string &name)
  {
    std::ifstream      in(softface_tests::source_file("run_multi_model.prm"));
    std::ostringstream text;
    text << in.rdbuf();
    std::string scene = std::regex_replace(text.str(),
                                           std::regex("set Models = [^\n]*"),
                                           "set Models = " + models);
    scene             = std::regex_replace(scene,
                               std::regex("set Output directory = [^\n]*"),
                               "set Output directory = " + name + "_output");
    std::ofstream(name + ".prm") << scene;

    softface::Simulator simulator;
    std::ostringstream  out, err;
    softface_tests::check_equal(name + ": exit code",
                                simulator.run(name + ".prm", out, err),
                                0);
    std::string                   listed;
    std::map<std::string, Answer> answers;
    for (const auto &run : simulator.runs())
      {
        listed += (listed.empty() ? "" : ", ") + run.label();
        Answer &answer      = answers[run.label()];
        answer.displacement = run.displacement;
        for (const auto &detail : run.statistics.details)
          if (!detail.depends_on_timing)
            answer.figures += detail.name + "=" + detail.formatted(17) + ";";
      }
    dealii::deallog << name << ": table lists " << listed << std::endl;
    return answers;
  }
} // namespace

SOFTFACE_TEST(model_order)
{
  auto forward = run_with_models(
    "linear fem, mass tensor, mass spring, nonlinear fem, reference fem",
    "model_order_forward");
  auto reversed = run_with_models(
    "reference fem, nonlinear fem, mass spring, mass tensor, linear fem",
    "model_order_reversed");
  softface_tests::check_equal("models in both", reversed.size(), 5);
  for (auto &[model, answer] : forward)
    {
      const Answer          &other      = reversed.at(model);
      dealii::Vector<double> difference = answer.displacement;
      difference -= other.displacement;
      softface_tests::check_below(model + ": max |u_forward - u_reversed| mm",
                                  difference.linfty_norm(),
                                  0.);
      softface_tests::check_equal(model + ": figures differ",
                                  answer.figures != other.figures,
                                  0);
    }
  const std::string &figures = reversed.at("mass tensor").figures;
  const auto         from    = figures.find("precision against=");
  dealii::deallog << "reversed list, mass tensor: "
                  << figures.substr(from, figures.find(';', from) - from)
                  << std::endl;
}

// The outputs register themselves from the shared library (one line at the
// bottom of each file in source/outputs/), like the models and effects; a
// second registration under a taken name is an error in every build. A
// scene that asks for every output (registered_outputs.prm) lists the files
// they wrote, with the rows of each CSV: adding an output, or one that stops
// writing, changes this test's expected output.

#include <softface/core/error.h>
#include <softface/outputs/interface.h>

#include "run_scene.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

using namespace softface;

SOFTFACE_TEST(registered_outputs)
{
  for (const auto &name : Outputs::registered_names())
    deallog << name << std::endl;

  std::string message;
  try
    {
      Outputs::internal::register_output("summary", {});
    }
  catch (const Error &e)
    {
      message = e.what();
    }
  deallog << "registering 'summary' again: " << message << std::endl;
  softface_tests::check_equal("the second registration is refused",
                              !message.empty(),
                              1);

  Simulator simulator;
  const int exit_code = softface_tests::run_scene(
    simulator, softface_tests::source_file("registered_outputs.prm"));
  softface_tests::check_equal("exit code", exit_code, 0);

  // The inputs copied beside the outputs are not outputs.
  std::vector<std::string> files;
  for (const auto &entry :
       std::filesystem::directory_iterator("registered_outputs_output"))
    if (entry.is_regular_file() && entry.path().extension() != ".prm")
      files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  for (const auto &file : files)
    {
      deallog << file;
      if (std::filesystem::path(file).extension() == ".csv")
        {
          std::ifstream in("registered_outputs_output/" + file);
          deallog << ": "
                  << std::count(std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>(),
                                '\n')
                  << " lines";
        }
      deallog << std::endl;
    }
}

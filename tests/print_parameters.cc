// 'softface --print-parameters' is what doc/parameters.prm documents: the
// two must be identical line by line. When a parameter or model is added,
// regenerate the file with
//   build/softface --print-parameters > doc/parameters.prm

#include <softface/simulator/simulator.h>

#include "tests.h"

#include <fstream>
#include <sstream>

using namespace dealii;

SOFTFACE_TEST(print_parameters)
{
  std::ostringstream printed;
  softface::Simulator::print_default_parameters(printed);
  std::ifstream      file(softface_tests::source_file("../doc/parameters.prm"));
  std::ostringstream documented;
  documented << file.rdbuf();

  std::istringstream a(printed.str()), b(documented.str());
  std::string        line_a, line_b;
  unsigned int       line = 0, first_difference = 0;
  while (true)
    {
      const bool more_a = static_cast<bool>(std::getline(a, line_a));
      const bool more_b = static_cast<bool>(std::getline(b, line_b));
      if (!more_a && !more_b)
        break;
      ++line;
      if (first_difference == 0 && (more_a != more_b || line_a != line_b))
        {
          first_difference = line;
          deallog << "printed:    " << (more_a ? line_a : "(end)") << std::endl;
          deallog << "documented: " << (more_b ? line_b : "(end)") << std::endl;
        }
    }
  softface_tests::check_above("lines", line, 100);
  softface_tests::check_equal(
    "first line where doc/parameters.prm differs (0: none; regenerate it "
    "with build/softface --print-parameters > doc/parameters.prm)",
    first_difference,
    0);
}

// The model plugins register themselves from the shared library (one line at
// the bottom of each source file); none may be dropped by the linker.

#include <softface/models/interface.h>

#include "tests.h"

#include <algorithm>

using namespace softface;

SOFTFACE_TEST(registered_models)
{
  const auto names = Models::registered_names();
  for (const auto &name : names)
    deallog << name << std::endl;
  for (const std::string name :
       {"linear fem", "mass spring", "mass tensor", "nonlinear fem"})
    softface_tests::check(std::count(names.begin(), names.end(), name) == 1,
                          name + " is registered once");
}

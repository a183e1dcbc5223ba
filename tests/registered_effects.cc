// The effect plugins register themselves from the shared library (one line
// at the bottom of each source file), like the models; a second
// registration under a taken name is an error in every build. Adding an
// effect adds one line to this test's expected output.

#include <softface/core/error.h>
#include <softface/effects/interface.h>

#include "tests.h"

using namespace softface;

SOFTFACE_TEST(registered_effects)
{
  for (const auto &name : Effects::registered_names())
    deallog << name << std::endl;

  std::string message;
  try
    {
      Effects::internal::register_effect("gravity", {});
    }
  catch (const Error &e)
    {
      message = e.what();
    }
  deallog << "registering 'gravity' again: " << message << std::endl;
  softface_tests::check_equal("the second registration is refused",
                              !message.empty(),
                              1);
}

// The model plugins register themselves from the shared library (one line at
// the bottom of each source file); none may be dropped by the linker, and a
// second registration under a taken name is an error in every build. Adding
// a model adds one line to this test's expected output.

#include <softface/core/error.h>
#include <softface/models/interface.h>

#include "tests.h"

using namespace softface;

SOFTFACE_TEST(registered_models)
{
  for (const auto &name : Models::registered_names())
    deallog << name << std::endl;

  std::string message;
  try
    {
      Models::internal::register_model("linear fem", {});
    }
  catch (const Error &e)
    {
      message = e.what();
    }
  deallog << "registering 'linear fem' again: " << message << std::endl;
  softface_tests::check_equal("the second registration is refused",
                              !message.empty(),
                              1);
}

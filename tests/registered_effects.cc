// The effect plugins register themselves from the shared library (one line
// at the bottom of each source file), like the models; a second
// registration under a taken name is an error in every build. Adding an
// effect adds one line to this test's expected output. Every registered
// model is checked against every registered effect (which contributions it
// honours), and a model that honours none is refused with one message
// naming the model and the effect.

#include <softface/core/error.h>
#include <softface/effects/interface.h>
#include <softface/models/interface.h>

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

  ParameterHandler prm;
  Models::declare_parameters(prm);
  Effects::declare_parameters(prm);
  // The entries without a usable default.
  prm.enter_subsection("Effects");
  prm.enter_subsection("sliding contact");
  prm.set("Segment", "bone");
  prm.leave_subsection();
  prm.enter_subsection("separated lips");
  prm.set("Slit point", "0, 0, 0");
  prm.leave_subsection();
  prm.leave_subsection();
  for (const auto &effect_name : Effects::registered_names())
    {
      const auto effect = Effects::create(effect_name, prm);
      for (const auto &model_name : Models::registered_names())
        {
          const auto  model = Models::create(model_name, prm);
          std::string refusal;
          try
            {
              Effects::check_supported(model_name,
                                       model->honoured_effects(),
                                       effect_name,
                                       *effect);
            }
          catch (const Error &e)
            {
              refusal = e.what();
            }
          deallog << model_name << " + " << effect_name << ": "
                  << (refusal.empty() ? "simulated" : refusal) << std::endl;
        }
      message.clear();
      try
        {
          Effects::check_supported("a model of no effects",
                                   SceneEffects::none,
                                   effect_name,
                                   *effect);
        }
      catch (const Error &e)
        {
          message = e.what();
        }
      deallog << message << std::endl;
      softface_tests::check_equal("a model of no effects is refused",
                                  !message.empty(),
                                  1);
    }
}

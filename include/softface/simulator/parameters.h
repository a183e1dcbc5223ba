#ifndef softface_simulator_parameters_h
#define softface_simulator_parameters_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace softface
{
  using namespace dealii;

  /// The Output section: where a run writes, and the model the others are
  /// compared to. What it writes is the outputs' (Outputs::Interface), each
  /// declaring its own entries of the section.
  struct OutputParameters
  {
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    std::string directory;
    std::string reference_model;
  };
} // namespace softface

#endif

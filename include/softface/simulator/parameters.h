#ifndef softface_simulator_parameters_h
#define softface_simulator_parameters_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace softface
{
  using namespace dealii;

  /// The Output section: where a run writes and what.
  struct OutputParameters
  {
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    std::string directory;
    bool        write_vtu                 = true;
    bool        write_nodal_displacements = false;
    std::string evaluation_points;
    std::string reference_model;
  };
} // namespace softface

#endif

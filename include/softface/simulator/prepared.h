#ifndef softface_simulator_prepared_h
#define softface_simulator_prepared_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/planning_list.h>
#include <softface/effects/interface.h>
#include <softface/models/interface.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/skin_output.h>
#include <softface/simulator/parameters.h>
#include <softface/simulator/simulator.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  /// What prepare() makes and run() uses.
  struct Simulator::Prepared
  {
    ParameterHandler prm;
    OutputParameters output;
    std::string      input_directory;
    std::vector<std::pair<std::string, std::unique_ptr<Models::Interface>>>
      models;
    std::vector<std::pair<std::string, std::unique_ptr<Effects::Interface>>>
                                effects;
    PlanningList                plannings;
    SkinParameters              skin_parameters;
    std::unique_ptr<SkinOutput> skin;
    // The outputs the scene asks for, and the run as they see it.
    std::vector<std::unique_ptr<Outputs::Interface>> outputs;
    std::unique_ptr<Outputs::Run>                    run;
    // On several MPI ranks every rank runs the scene; rank 0 alone writes
    // the outputs.
    bool writes_outputs = true;
    // On several MPI ranks: the partition the distributed models share, and
    // on which the ranks write their pieces of the fields.
    std::shared_ptr<SharedDistributedLayout> layout;
    // Do the members of the groups of ranks hold no cells of the scene?
    bool members_without_cells = false;
  };
} // namespace softface

#endif

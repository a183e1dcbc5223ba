#ifndef softface_simulator_h
#define softface_simulator_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace softface
{
  using namespace dealii;

  /**
   * Runs one scene file: parse it, build the scene, turn the planning into
   * join-point displacements, run every selected model on them and write the
   * outputs.
   */
  class Simulator
  {
  public:
    /**
     * Declare every parameter. The Segment and Motion subsections depend on
     * the names a file lists, so a file is read twice: once tolerantly for
     * those names, then strictly with everything declared.
     */
    static void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &segment_names,
                       const std::vector<std::string> &moved_segments);

    /// Fill @p prm from @p filename (both passes).
    static void
    read_parameters(const std::string &filename, ParameterHandler &prm);

    /// The documented default parameter file.
    static void
    print_default_parameters(std::ostream &out);

    /// Run the scene in @p filename; returns the process exit code.
    static int
    run(const std::string &filename);
  };
} // namespace softface

#endif

#ifndef softface_simulator_input_files_h
#define softface_simulator_input_files_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace softface
{
  /**
   * Make every input file a scene names (the mesh, the CT and label volumes,
   * the post-operative skull, CT and surfaces, the skins, the evaluation
   * points) an absolute path in @p prm. A relative file is taken from the
   * parameter file's folder, @p input_directory; the expanded parameter file
   * written into the output folder then runs again from there, or from
   * anywhere. Keywords ('auto', 'none') and empty entries stay.
   */
  void
  make_input_files_absolute(dealii::ParameterHandler &prm,
                            const std::string        &input_directory);
} // namespace softface

#endif

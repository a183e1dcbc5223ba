#ifndef softface_patient_commands_h
#define softface_patient_commands_h

#include <deal.II/base/parameter_handler.h>

#include <ostream>
#include <string>

namespace softface
{
  namespace Patient
  {
    /**
     * The patient subcommands on a read scene file @p prm (from
     * @p filename): its patient stages up to @p stage ("phantom", "segment"
     * or "mesh"), writing their files into the patient work directory
     * (<@p output_directory>/patient unless the scene names one); or, after
     * them, "postop" (a post-operative skull: each bone part moved by the
     * scene's Planning) or "plan" (each bone part registered to the
     * post-operative skull by ICP from the scene's Planning, written as
     * planning.prm); or "register" (the post-operative CT of
     * Scene/Patient/Registration registered to the pre-operative one,
     * written with the post-operative surfaces carried into the
     * pre-operative frame into @p output_directory); or "preview" (the
     * stages up to the bone parts and pictures of the CT with the labels,
     * parts, cuts, seed points and region of interest, preview.h). Returns
     * the process exit code.
     */
    int
    run_command(dealii::ParameterHandler &prm,
                const std::string        &filename,
                const std::string        &stage,
                const std::string        &output_directory,
                std::ostream             &out);
  } // namespace Patient
} // namespace softface

#endif

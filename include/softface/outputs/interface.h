#ifndef softface_outputs_interface_h
#define softface_outputs_interface_h

#include <deal.II/base/parameter_handler.h>

#include <softface/core/scene.h>
#include <softface/models/interface.h>
#include <softface/outputs/report.h>

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  class SharedDistributedLayout;
  class SkinOutput;

  /**
   * What a run writes: a plugin family like ASPECT's postprocessors. Each
   * output is one file in source/outputs/, registered with
   * SOFTFACE_REGISTER_OUTPUT, declares its own entries of the Output
   * section (the entry that asks for it, e.g. 'Write VTU') and writes its
   * files from a read-only view of the run (Outputs::Run). Every registered
   * output is created for every scene; those the scene does not ask for
   * write nothing.
   */
  namespace Outputs
  {
    /**
     * The run as outputs see it: the scene, the models' runs (filled as
     * they answer) and where to write. Every MPI rank holds one; only
     * where writes_outputs is set (rank 0) are whole-run files written.
     */
    struct Run
    {
      const Scene                         &scene;
      const std::vector<Report::ModelRun> &runs;
      /// The model the others are compared to ('Output/Reference model').
      const std::string &reference_model;
      /// 'Output/Output directory' (made on rank 0 before the models run).
      const std::string &directory;
      /// Does this rank write the files of the whole run (rank 0)?
      bool writes_outputs;
      /// On several ranks: the partition the distributed models share
      /// (built when first asked for, collectively), and whether the members
      /// of the groups of ranks hold no cells of the scene.
      SharedDistributedLayout *layout                = nullptr;
      bool                     members_without_cells = false;
      /// Does the scene map its answers onto a skin ('Skin/Skin surface'),
      /// known on every rank.
      bool maps_skins = false;
      /// The skin and its mappings (step A done) on the rank that maps
      /// them (rank 0); nullptr without a skin and on the other ranks.
      SkinOutput *skin = nullptr;
    };

    /// "mass tensor" -> "mass_tensor", "linear fem, bone rotation angle 5"
    /// -> "linear_fem_bone_rotation_angle_5"
    std::string
    file_name_of(const std::string &model);

    class Interface
    {
    public:
      virtual ~Interface() = default;

      /**
       * Reads the output's entries; @p prm is inside the Output section.
       * Relative file names are relative to @p input_directory.
       */
      virtual void
      parse_parameters(ParameterHandler  &prm,
                       const std::string &input_directory) = 0;

      /// Does the scene ask for this output?
      virtual bool
      requested() const = 0;

      /**
       * Before any model runs: read and check what the output needs (an
       * error in its input stops the run here). Called on every rank, only
       * if requested.
       */
      virtual void
      prepare(const Run &run, std::ostream &out);

      /**
       * After each plan a model answered (its displacement is in
       * @p model_run; @p from_basis: combined from its response basis, its
       * own field not updated). Called on every rank, only if requested.
       */
      virtual void
      add_answer(const Run              &run,
                 const Report::ModelRun &model_run,
                 Models::Interface      &model,
                 bool                    from_basis);

      /// After every model ran. Called on every rank, only if requested.
      virtual void
      write(const Run &run, std::ostream &out) = 0;

      /// What it writes, for the closing line ("summary.csv").
      virtual std::string
      files(const Run &run) const = 0;
    };

    /// An output every run writes (or, like the skins, one asked for
    /// elsewhere), with no entries of its own in the Output section.
    class Unconditional : public Interface
    {
    public:
      static void
      declare_parameters(ParameterHandler &)
      {}

      void
      parse_parameters(ParameterHandler &, const std::string &) override
      {}

      bool
      requested() const override
      {
        return true;
      }
    };

    struct Registration
    {
      /// What the output writes, for 'softface --help'.
      std::string description;
      /// Declares the output's entries; the handler is inside Output.
      std::function<void(ParameterHandler &)>     declare_parameters;
      std::function<std::unique_ptr<Interface>()> factory;
    };

    /// Every output's entries; @p prm is inside the Output section.
    void
    declare_parameters(ParameterHandler &prm);

    /// Every registered output, in the order of their names, each having
    /// parsed its entries; @p prm is inside the Output section.
    std::vector<std::unique_ptr<Interface>>
    create_all(ParameterHandler &prm, const std::string &input_directory);

    /// The registered outputs' names, in alphabetical order.
    std::vector<std::string>
    registered_names();

    /// One line per output: name and description (for --help).
    std::string
    describe_registered();

    namespace internal
    {
      /// Throws if @p name is registered already.
      bool
      register_output(const std::string &name, Registration registration);
    } // namespace internal
  }   // namespace Outputs
} // namespace softface

/**
 * Register an output under @p name. The class needs a default constructor
 * and a static declare_parameters(prm) that declares its entries in the
 * Output section.
 */
#define SOFTFACE_REGISTER_OUTPUT(classname, name, description)   \
  namespace                                                      \
  {                                                              \
    const bool softface_registered_output_##classname =          \
      softface::Outputs::internal::register_output(              \
        name,                                                    \
        {description,                                            \
         &classname::declare_parameters,                         \
         []() -> std::unique_ptr<softface::Outputs::Interface> { \
           return std::make_unique<classname>();                 \
         }});                                                    \
  }

#endif

// The 'skins' output: every model's predicted skin (PLY, VTP), its distances
// to the post-operative skin, skin.csv and the table (SkinOutput). The skin
// and step A of its mappings are made before the models run (the Skin
// section); this output adds each answer and writes them.

#include <softface/core/on_rank_0.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/skin_output.h>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      class Skins : public Unconditional
      {
      public:
        void
        add_answer(const Run              &run,
                   const Report::ModelRun &model_run,
                   Models::Interface &,
                   bool) override
        {
          // Rank 0 maps for all; its error is every rank's. Every rank
          // knows whether the run maps skins.
          if (run.maps_skins)
            on_rank_0(MPI_COMM_WORLD, [&]() {
              run.skin->add_model(model_run.label(),
                                  run.scene,
                                  model_run.displacement);
            });
        }

        void
        write(const Run &run, std::ostream &out) override
        {
          if (!run.writes_outputs || run.skin == nullptr)
            return;
          std::vector<std::string> labels;
          for (const auto &model_run : run.runs)
            labels.push_back(model_run.label());
          run.skin->order_rows(labels);
          run.skin->write(out);
        }

        std::string
        files(const Run &run) const override
        {
          return run.maps_skins ? "skin.csv, skin_*.ply/.vtp" : "";
        }
      };
    } // namespace

    SOFTFACE_REGISTER_OUTPUT(Skins,
                             "skins",
                             "skin.csv, skin_<model>.ply/.vtp ('Skin/Skin "
                             "surface'): the predicted skins and their "
                             "distances to the post-operative skin")
  } // namespace Outputs
} // namespace softface

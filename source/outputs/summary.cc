// The 'summary' output: summary.csv, one row per model and plan in full
// precision (Report::write_summary_csv); every run writes it.

#include <softface/outputs/interface.h>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      class Summary : public Unconditional
      {
      public:
        void
        write(const Run &run, std::ostream &) override
        {
          if (run.writes_outputs)
            Report::write_summary_csv(run.scene,
                                      run.runs,
                                      run.reference_model,
                                      run.directory + "/summary.csv");
        }

        std::string
        files(const Run &) const override
        {
          return "summary.csv";
        }
      };
    } // namespace

    SOFTFACE_REGISTER_OUTPUT(Summary,
                             "summary",
                             "summary.csv: one row per model (and plan), "
                             "full precision (always written)")
  } // namespace Outputs
} // namespace softface

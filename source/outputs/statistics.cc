// The 'statistics' output: the table with timings, extras and a column
// legend, aligned (Report::write_statistics); every run writes it.

#include <softface/outputs/interface.h>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      class Statistics : public Unconditional
      {
      public:
        void
        write(const Run &run, std::ostream &) override
        {
          if (run.writes_outputs)
            Report::write_statistics(run.scene,
                                     run.runs,
                                     run.directory + "/statistics");
        }

        std::string
        files(const Run &) const override
        {
          return "statistics";
        }
      };
    } // namespace

    SOFTFACE_REGISTER_OUTPUT(Statistics,
                             "statistics",
                             "statistics: the table with timings, DoFs, "
                             "residuals and memory, aligned (always written)")
  } // namespace Outputs
} // namespace softface

#ifndef softface_serve_parameters_h
#define softface_serve_parameters_h

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Serve
  {
    /// The Serve section: what `softface serve` offers and where.
    struct Parameters
    {
      static void
      declare_parameters(ParameterHandler &prm);
      /// Throws a clear error for a bad entry.
      void
      parse_parameters(ParameterHandler &prm);

      std::string              address = "127.0.0.1";
      unsigned int             port    = 8080;
      std::vector<std::string> models;
      double                   translation_limit = 20.; ///< mm
      double                   rotation_limit    = 30.; ///< degrees
      /// The page's files (index.html, app.js and node_modules/three).
      std::string web_directory;
    };
  } // namespace Serve
} // namespace softface

#endif

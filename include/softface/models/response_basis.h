#ifndef softface_models_response_basis_h
#define softface_models_response_basis_h

#include <deal.II/base/point.h>
#include <deal.II/lac/vector.h>

#include <softface/core/planning.h>
#include <softface/core/scene.h>
#include <softface/models/interface.h>

#include <vector>

namespace softface
{
  using namespace dealii;

  namespace Models
  {
    /**
     * Every plan at the cost of a vector combination, for a model whose
     * answer is affine in the motion (Interface::linear_in_motion()).
     *
     * A moved segment's join points move by x -> R (x - c) + c + t, so by
     *   d(x) = (R - I) (x - c_s) + t_s,   t_s = R (c_s - c) + c + t - c_s,
     * which is linear in the 12 entries of (R - I, t_s) for any fixed point
     * c_s (the segment's join centroid here). The model's answer to the
     * join displacement d_ij(x) = e_i (x - c_s)_j (9 of them) and to the
     * unit translations (3) of every moved segment, less its answer to no
     * motion at all (the body force's, zero without one), gives every plan
     * as that answer plus the responses weighted by the plan's entries:
     * the model's own answer up to its solver's tolerance.
     */
    class ResponseBasis
    {
    public:
      /// The solves build() takes for @p n_segments moved segments.
      static unsigned int
      n_solves(const Scene &scene, const unsigned int n_segments);

      /**
       * Solve @p model (set up on @p scene) once for each response of every
       * segment in @p segments (and once without motion if the scene has
       * a body force). Throws if the model's answer is not affine in the
       * motion on this scene.
       */
      void
      build(Interface                       &model,
            const Scene                     &scene,
            const std::vector<unsigned int> &segments);

      /**
       * The model's displacement under @p planning, which must move only
       * segments of the basis.
       */
      void
      combine(const Planning &planning, Vector<double> &displacement) const;

      /// The responses' memory in MB.
      double
      memory_mb() const;

      /// The join motion (mm) each response is solved for before it is
      /// scaled to a unit entry: models that stop on absolute figures (the
      /// mass tensor model's mm per sweep) then answer each response as
      /// precisely as a plan of that size.
      double typical_motion = 10.;

      /// Totals over the basis solves: iterations, and the largest relative
      /// residual.
      unsigned int total_iterations = 0;
      double       largest_residual = 0.;
      /// The models' warnings in the basis solves, each once.
      std::vector<std::string> warnings;

    private:
      const Scene              *scene = nullptr;
      std::vector<unsigned int> segments;
      std::vector<Point<3>>     centre; ///< c_s of each segment
      /// The answer without motion (empty: zero).
      Vector<double> offset;
      /// 12 per segment: the 9 entries of R - I (row-major), then t.
      std::vector<Vector<double>> responses;
    };
  } // namespace Models
} // namespace softface

#endif

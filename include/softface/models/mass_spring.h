#ifndef softface_models_mass_spring_h
#define softface_models_mass_spring_h

#include <softface/core/point_mesh.h>
#include <softface/models/interface.h>
#include <softface/models/point_constraints.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace softface
{
  class PointExchange;
  class PointSweeps;
  struct BlockColouring;

  namespace Models
  {
    /**
     * The tetrahedral Mass Spring Model of Mollemans et al. 2007 (Sec. 2.2):
     * one linear spring per mesh edge with k = E sum(V of the tetrahedra
     * sharing the edge) / L0^2 (eq. 5, Gelder 1998), nonlinear in the positions
     * (eq. 4).
     *
     * Static equilibrium by local steepest descent: a point moves along its
     * force F_i by F_i / sum_j k_j (the step that would zero the force if the
     * springs were aligned with it), never by more than a fraction of its
     * shortest spring (so no spring can flip in one step), updated in place.
     * Dynamic cut-out: a sweep visits only the neighbours of points that
     * moved, and a point moves only while its step, |F_i| / sum k, exceeds
     * the threshold. Optionally ("Prevent inversion"), a step that would
     * invert a tetrahedron is halved until it does not (at most 8 times,
     * else not taken). The join points' motion is applied in load steps no
     * longer than the step bound of their shortest spring, so that a moving
     * bone cannot jump past its free neighbours. At the end, inverted
     * tetrahedra (a spring that flips over inverts the tetrahedra around it)
     * are counted and reported.
     *
     * On several MPI ranks each rank moves the points of its
     * range of blocks (PointExchange), the colours in turn with a ghost
     * exchange after each: the serial sweep, update for update, so the
     * answer and the sweeps are the serial ones. A ghost that moved wakes
     * its neighbours, and the sweeps end when no rank has a point to move.
     */
    class MassSpring : public Interface
    {
    public:
      MassSpring();
      ~MassSpring() override;

      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;
      /// Tissues per cell and body forces.
      unsigned int
      honoured_effects() const override;
      /// True: on several ranks it reads the cells through its PointMesh,
      /// which rank 0 sends to ranks without them.
      bool
      runs_without_scene_cells() const override;

      void
      set_stop_threshold(const double threshold_mm);
      void
      set_prevent_inversion(const bool prevent);

      struct Spring
      {
        unsigned int a, b;
        double       rest_length;
        double       stiffness; ///< N/mm
      };
      const std::vector<Spring> &
      springs() const;

      struct Report
      {
        unsigned int       sweeps        = 0;
        unsigned int       load_steps    = 0;
        unsigned long long point_updates = 0;
        double             max_step      = 0.; ///< |F|/sum k at the end, mm
        /// Tetrahedra with a free point turned inside out at the end (a
        /// flipped spring inverts the tetrahedra around it); those of join
        /// points only move as the planning moves them.
        unsigned int inverted_tetrahedra = 0;
        /// Updates not taken because every halving of the step would have
        /// inverted a tetrahedron.
        unsigned long long blocked_updates = 0;
        /// On several MPI ranks: the load steps after which the ranks'
        /// blocks were shared again by that step's updates and changed.
        unsigned int rebalances = 0;
      };
      const Report &
      report() const;

    protected:
      void
      do_setup(const Scene &scene) override;
      void
      do_solve(const Vector<double> &prescribed,
               Vector<double>       &displacement) override;

    private:
      double       stop_threshold    = 1e-3;
      double       max_step_fraction = 0.25;
      unsigned int max_sweeps        = 200000;
      bool         prevent_inversion = false;
      bool         warm_start        = true;
      /// The last answer's positions and join displacement (Warm start).
      std::vector<Point<3>> last_position;
      Vector<double>        last_prescribed;

      const Scene *scene = nullptr;
      /// On several MPI ranks: the points this rank moves.
      std::unique_ptr<PointExchange> exchange;
      std::unique_ptr<PointMesh>     mesh;
      /// The order of a sweep's updates (BlockColouring).
      std::unique_ptr<BlockColouring> colouring;
      std::vector<Spring>             spring_list;
      // Per point: its springs run along its neighbours (mesh->row_start,
      // ->neighbour); the spring of each such edge and the sum of the
      // point's spring constants.
      std::vector<unsigned int> spring_of;
      std::vector<double>       total_stiffness;
      // Vertex constraints (sliding contact, lips) per point: the index of
      // its constraint in point_constraints, or -1 (make_point_constraints).
      std::vector<PointConstraint> point_constraints;
      std::vector<int>             constraint_of_point;

      /// The local updates of a solve and its load steps' stop
      /// (PointSweeps' model).
      class LocalUpdates;
      /// The load steps the join motion needs (and the join points that
      /// move, into @p updates).
      unsigned int
      load_steps(LocalUpdates &updates) const;
      /// On several MPI ranks, after a load step: the blocks shared again by
      /// that step's updates. Collective. True if they moved.
      bool
      rebalance(PointSweeps &sweeps, std::vector<Point<3>> &x);
      /// The solve's figures into report(), the statistics and the details.
      void
      report_solve(const LocalUpdates &updates,
                   const PointSweeps  &sweeps,
                   const double        initial,
                   const unsigned int  n_load_steps,
                   const unsigned int  rebalances,
                   const bool          warm);
      /// Warn of inverted tetrahedra at equilibrium; throw without one.
      void
      check_equilibrium(const unsigned int sweeps,
                        const unsigned int n_load_steps);

      Report last_report;
    };
  } // namespace Models
} // namespace softface

#endif

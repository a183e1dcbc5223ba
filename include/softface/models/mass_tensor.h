#ifndef softface_models_mass_tensor_h
#define softface_models_mass_tensor_h

#include <deal.II/base/tensor.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <softface/core/point_mesh.h>
#include <softface/fe/linear_solver.h>
#include <softface/fe/vertex_constraints.h>
#include <softface/models/block_colouring.h>
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

  namespace Models
  {
    /**
     * The Mass Tensor Model of Mollemans et al. 2007 (Sec. 2.3, after Cotin et
     * al. 2000). Every tetrahedron's linear-elastic stiffness (eqs. 6-8) is
     * summed into one 3x3 tensor K_jj per point and one K_jk per edge
     * (eqs. 9-10): exactly the 3x3 blocks of the linear FEM stiffness. Points
     * are the mesh vertices in the order of the shared DoF layout (point p
     * owns DoFs 3p, 3p+1, 3p+2).
     *
     * Extension 1 (2.3.2): the rest position is found point by point,
     * u_j = -K_jj^-1 sum_k K_jk u_k (eq. 12) with K_jj^-1 precomputed, in
     * Gauss-Seidel order (in place) or Jacobi order (all from the previous
     * sweep); optionally relaxed (damped Jacobi, or SOR).
     *
     * Extension 2 (2.3.3): a point's gradient is the mean length of its
     * last W updates (mm per sweep). A point stops once its gradient is below
     * the threshold; with the active set, a sweep visits only points that
     * have not stopped or whose neighbour moved by more than the threshold in
     * the previous sweep (the only points whose force can have changed).
     *
     * The precision (paper, Table 1, Fig. 1) is the distance to the converged
     * answer of the same equations, which the model solves itself: its
     * tensors as one sparse matrix, factorised once per scene.
     *
     * On several MPI ranks each rank sweeps the points of its
     * range of blocks (PointExchange), the colours in turn with a ghost
     * exchange after each: the serial sweep, update for update. Every
     * decision of the stop criterion is taken on global figures, so the
     * ranks' answer, sweeps and stop are the serial ones. Each rank builds
     * the tensors of its points' rows only, from its PointMesh, which is
     * whole on every rank (and sent by rank 0 where a rank holds no
     * cells).
     */
    class MassTensor : public Interface
    {
    public:
      MassTensor();
      ~MassTensor() override;

      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;
      /// Tissues per cell and body forces.
      unsigned int
      honoured_effects() const override;
      /// True without unilateral contact (the active set is not linear).
      bool
      linear_in_motion(const Scene &scene) const override;
      /// "linear fem": the tensors are the blocks of its stiffness.
      std::string
      converged_equivalent() const override;
      /// True: on several ranks it reads the cells through its PointMesh,
      /// which rank 0 sends to ranks without them.
      bool
      runs_without_scene_cells() const override;

      /// Set the solution scheme in code (tests, benchmarks).
      void
      set_scheme(const bool         gauss_seidel,
                 const double       stop_gradient_threshold,
                 const unsigned int gradient_window,
                 const bool         active_set);
      /// Relaxation factor of the updates (1: the paper's eq. 12; 0: 'auto',
      /// 1.8 with Gauss-Seidel order and 1 with Jacobi).
      void
      set_relaxation(const double factor);
      /// The factor the updates use.
      double
      relaxation_factor() const;
      /// Distance to the answer (mm) below which a stop that the paper's
      /// criterion proposes is accepted; 0: the paper's criterion alone.
      void
      set_stop_distance(const double distance);
      /// Also compute the converged answer and report the precision.
      void
      set_report_precision(const bool report);
      /// Write the per-sweep precision history there (empty: off).
      void
      set_precision_history_file(const std::string &filename);

      unsigned int
      n_points() const;
      /// Does this process hold point @p j's tensors (the K_jk of its row)?
      /// Every point's on one rank; on several, those of the points it owns.
      bool
      holds_tensors(const unsigned int j) const
      {
        return j >= first_row && j - first_row < diagonal.size();
      }

      /// K_jk (K_jj for j == k); zero if j and k share no tetrahedron. Point
      /// @p j's tensors must be this process's (holds_tensors()).
      Tensor<2, 3>
      tensor(const unsigned int j, const unsigned int k) const;

      /// The paper's Table 1 and the work done, for the last solve.
      struct Report
      {
        unsigned int       sweeps        = 0;
        unsigned long long point_updates = 0;
        double             max_gradient  = 0.; ///< mm per sweep, at the end
        /// Largest and mean distance (mm) of a free point to the converged
        /// answer (the paper's "minimal" and mean precision); -1 if not
        /// computed.
        double precision_max  = -1.;
        double precision_mean = -1.;
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
      using Block = std::array<double, 9>;

      /// The converged answer of the same equations for @p prescribed.
      void
      solve_converged(const Vector<double> &prescribed,
                      Vector<double>       &converged);

      bool         gauss_seidel            = true;
      double       relaxation              = 0.; ///< 0: 'auto'
      double       stop_gradient_threshold = 1e-3;
      unsigned int gradient_window         = 10;
      bool         use_active_set          = true;
      unsigned int max_sweeps              = 100000;
      double       convergence_tolerance   = 1e-9;
      double       stop_distance           = 0.1;
      bool         report_precision        = false;
      std::string  precision_history_file;

      const Scene *scene = nullptr;
      /// On several MPI ranks: the points this rank updates.
      std::unique_ptr<PointExchange> exchange;

      // Block-CSR on the points' neighbours (mesh->row_start, ->neighbour):
      // K_jk in coupling[...], K_jj and K_jj^-1 per point. A process holds
      // the rows of every point, or on several MPI ranks of the range of
      // points it owns (join points among them), from point first_row and
      // neighbour entry first_entry = row_start[first_row] on (the
      // accessors below). whole_coupling and whole_diagonal: every row, on
      // several ranks, once the converged answer has asked for them.
      std::unique_ptr<PointMesh> mesh;
      std::vector<Block>         coupling;
      std::vector<Block>         diagonal;
      std::vector<Block>         diagonal_inverse;
      unsigned int               first_row   = 0;
      std::size_t                first_entry = 0;
      std::vector<Block>         whole_coupling;
      std::vector<Block>         whole_diagonal;

      /// K_jk of neighbour entry @p i (row_start[j] <= i < row_start[j+1])
      /// of a row this process holds.
      const double *
      coupling_of(const std::size_t i) const
      {
        return coupling[i - first_entry].data();
      }
      /// K_jj^-1 of a point this process holds.
      const double *
      inverse_of(const unsigned int j) const
      {
        return diagonal_inverse[j - first_row].data();
      }
      /// The paper's eqs. 9-10: the tensors of the rows of points
      /// [@p first, @p end) (each tetrahedron at one of them adds to their
      /// rows).
      void
      make_tensors(const unsigned int  first,
                   const unsigned int  end,
                   std::vector<Block> &coupling_rows,
                   std::vector<Block> &diagonal_rows) const;
      // Vertex constraints (sliding contact, lips) per point: the index of
      // its constraint in point_constraints, or -1 (make_point_constraints).
      std::vector<PointConstraint> point_constraints;
      std::vector<int>             constraint_of_point;
      /// The order of the updates in a sweep, and what may run at once.
      std::unique_ptr<BlockColouring> colouring;

      /// The local problem's minimiser at point @p j: K_jj^-1 (f_j - sum_k
      /// K_jk u_k) (the paper's eq. 12).
      void
      local_optimum(const unsigned int  j,
                    const double *const u,
                    const double *const load,
                    double              opt[3]) const;
      /// Move @p opt, point j's minimiser, onto its constraint (and, for a
      /// pair, the partner point too, which wakes its neighbours in
      /// @p queued if it moved by more than @p threshold).
      void
      constrained_update(const unsigned int         j,
                         double                     opt[3],
                         double *const              u,
                         const double *const        load,
                         const Vector<double>      &prescribed,
                         const double               threshold,
                         PointSweeps               &sweeps,
                         std::vector<unsigned int> &queued) const;

      /// Queue the first sweep's points: the free neighbours of join points
      /// that move (every free point without the active set, or with a
      /// load or constraints).
      void
      queue_first_sweep(PointSweeps &sweeps, const double *const u) const;
      /// The local updates of a solve and its stop (PointSweeps' model).
      class LocalUpdates;
      /// The solve's figures into report(), the statistics and the details.
      void
      report_solve(const LocalUpdates   &updates,
                   const PointSweeps    &sweeps,
                   const double          sweep_time,
                   const Vector<double> &prescribed,
                   const Vector<double> &displacement,
                   const Vector<double> &converged,
                   const bool            reused_answer);
      /// The residual force on the free points relative to the force at
      /// the start (that of the join points). Collective.
      double
      relative_residual(const Vector<double> &prescribed,
                        const double *const   u) const;

      // The converged answer's system, built when first needed.
      SparsityPattern      converged_sparsity;
      SparseMatrix<double> converged_matrix;
      LinearSolver         converged_solver;
      bool                 converged_ready = false;
      // With vertex constraints: K before elimination (for the contact
      // forces), the constrained matrix and its constraints.
      SparseMatrix<double>                 converged_unconstrained;
      SparseMatrix<double>                 converged_condensed;
      std::unique_ptr<VertexConstraintSet> converged_constraints;
      std::vector<bool>                    converged_condensed_for;

      Report last_report;
    };
  } // namespace Models
} // namespace softface

#endif

#ifndef softface_fe_linear_solver_h
#define softface_fe_linear_solver_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/fe/sparse_cholesky.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

class Epetra_MultiVector;
namespace Teuchos
{
  class ParameterList;
}

namespace softface
{
  using namespace dealii;

  /**
   * The linear solves of the FEM models, written once: the
   * Jacobi-preconditioned GMRES of Mollemans et al. 2007, CG or GMRES with
   * Trilinos ML smoothed aggregation given the six rigid-body modes of the
   * layout (deal.II 9.4 hands ML only the translations), and a sparse Cholesky
   * factorisation (CHOLMOD) whose ordering is reused when the matrix changes.
   *
   * For matrices that change (Newton tangents) ML is built once, on the
   * first matrix or the one given to build_amg(), and rebuilt when a solve
   * gets slow: a solve over 'AMG rebuild iterations' rebuilds it for the
   * following solves, and one still running at twice that many is continued
   * from where it got to with ML rebuilt at once. CG stops when it meets
   * negative curvature (p^T A p <= 0: the matrix is not positive definite),
   * where it has no answer, as the Cholesky factorisation fails.
   */
  class LinearSolver
  {
  public:
    struct Parameters
    {
      /// "gmres jacobi", "cg amg", "gmres amg" or "direct".
      std::string  method                    = "cg amg";
      double       relative_tolerance        = 1e-10;
      unsigned int max_iterations            = 20000;
      unsigned int gmres_restart             = 50;
      unsigned int amg_smoother_sweeps       = 2;
      double       amg_aggregation_threshold = 0.02;
      /// Smooth ML's prolongators (smoothed aggregation) or not.
      bool amg_smoothed_aggregation = false;
      /// 0: ML is built once and never rebuilt (a fixed matrix).
      unsigned int amg_rebuild_iterations = 0;

      /**
       * Declare the tuning entries, with this object's values as defaults:
       * GMRES restart, AMG smoother sweeps, AMG aggregation threshold, AMG
       * prolongator and,
       * if @p with_rebuild, AMG rebuild iterations. The method, tolerance and
       * iteration limit are the model's own entries (their names and
       * meaning differ between a linear solve and a Newton step).
       */
      void
      declare_tuning_parameters(ParameterHandler &prm,
                                const bool        with_rebuild) const;
      void
      parse_tuning_parameters(ParameterHandler &prm, const bool with_rebuild);
    };

    /// What a solve achieved.
    struct Result
    {
      bool         converged             = false;
      unsigned int iterations            = 0;
      double       relative_residual     = 0.;    ///< iterative methods
      bool         negative_curvature    = false; ///< CG met p^T A p <= 0
      bool         not_positive_definite = false; ///< Cholesky failed
    };

    /**
     * Choose the method for the layout whose DoFs have these support points
     * and components (ML's near-null space); forgets any earlier matrix.
     */
    void
    initialize(const Parameters                &parameters,
               const std::vector<Point<3>>     &dof_points,
               const std::vector<unsigned int> &dof_component);

    /// The same for the scene's shared layout.
    void
    initialize(const Parameters &parameters, const Scene &scene);

    /// The support points and components of the scene's shared layout's
    /// DoFs (its vertices').
    static void
    scene_dof_points(const Scene               &scene,
                     std::vector<Point<3>>     &points,
                     std::vector<unsigned int> &component);

    /**
     * Solve with @p matrix from now on (it is referenced, not copied, until
     * the next call). Jacobi is set up on it, ML built on it unless it was
     * built before, and the direct method factorises it; returns false if
     * the factorisation finds it not positive definite.
     */
    bool
    set_matrix(const SparseMatrix<double> &matrix);

    /// Build ML on @p matrix now (e.g. the stiffness at rest, for tangents).
    void
    build_amg(const SparseMatrix<double> &matrix);

    /**
     * ML's parameters for elasticity on @p matrix, serial or distributed:
     * the six rigid-body modes (rotations about @p centroid) of the DoFs this
     * process owns, which have the support points @p dof_points and
     * components @p dof_component in the matrix's order, aggregated as points
     * when each point's DoFs are 3k..3k+2, and the prolongator and smoother
     * that @p parameters choose. The returned vectors back the list's null
     * space: keep them until ML is built.
     */
    static std::array<std::unique_ptr<Epetra_MultiVector>, 2>
    amg_parameters(const Parameters                     &parameters,
                   const TrilinosWrappers::SparseMatrix &matrix,
                   const std::vector<Point<3>>          &dof_points,
                   const std::vector<unsigned int>      &dof_component,
                   const Point<3>                       &centroid,
                   Teuchos::ParameterList               &list);

    /// Solve; @p solution is the initial guess of an iterative method.
    Result
    solve(const Vector<double> &rhs, Vector<double> &solution);

    const Parameters &
    parameters() const;

    unsigned int
    n_amg_builds() const;
    unsigned int
    n_factorizations() const;

  private:
    /// One CG or GMRES run of at most @p limit iterations from @p solution.
    bool
    iterate(const Vector<double> &rhs,
            Vector<double>       &solution,
            const unsigned int    limit,
            Result               &result);

    Parameters                  prm;
    std::vector<Point<3>>       dof_points;
    std::vector<unsigned int>   dof_component;
    const SparseMatrix<double> *matrix = nullptr;

    PreconditionJacobi<SparseMatrix<double>> jacobi;
    TrilinosWrappers::SparseMatrix           amg_matrix;
    TrilinosWrappers::PreconditionAMG        amg;
    bool                                     amg_built = false;
    SparseCholesky                           cholesky;
    unsigned int                             amg_builds     = 0;
    unsigned int                             factorizations = 0;
  };
} // namespace softface

#endif

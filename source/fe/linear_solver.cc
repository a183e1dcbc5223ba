// The FEM models' linear solves (fe): method choice, Trilinos ML with the
// six rigid-body modes, its rebuild policy for changing Newton tangents, the
// negative-curvature stop of CG, and the reused Cholesky factorisation.

#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <softface/core/error.h>
#include <softface/fe/linear_solver.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <algorithm>

namespace softface
{
  void
  LinearSolver::Parameters::declare_tuning_parameters(
    ParameterHandler &prm,
    const bool        with_rebuild) const
  {
    prm.declare_entry("GMRES restart",
                      std::to_string(gmres_restart),
                      Patterns::Integer(1),
                      "Krylov vectors GMRES keeps before it restarts.");
    prm.declare_entry("AMG smoother sweeps",
                      std::to_string(amg_smoother_sweeps),
                      Patterns::Integer(1, 10),
                      "Chebyshev smoother sweeps before and after each "
                      "coarse correction of the AMG V-cycle.");
    prm.declare_entry("AMG aggregation threshold",
                      Patterns::Tools::to_string(amg_aggregation_threshold),
                      Patterns::Double(0., 1.),
                      "ML's aggregation threshold: matrix entries smaller "
                      "than this (relative) are dropped when aggregating.");
    prm.declare_entry(
      "AMG prolongator",
      amg_smoothed_aggregation ? "smoothed" : "unsmoothed",
      Patterns::Selection("unsmoothed|smoothed"),
      "How ML makes a coarse level: 'unsmoothed' takes the aggregates (of "
      "points, with the rigid-body modes) as they are; 'smoothed' smooths "
      "them with a damped Jacobi step (smoothed aggregation, ML's default), "
      "which needs fewer CG iterations but a setup two to three times as "
      "costly. Measured on the gmsh cubes of benchmarks/peers, setup + CG: "
      "105k tetrahedra 0.30 + 0.57 s (37 iterations) against 0.69 + 0.47 s "
      "(21); 491k 1.44 + 3.03 s (46) against 3.62 + 2.42 s (24). The "
      "linear FEM (one solve) defaults to 'unsmoothed', the nonlinear FEM "
      "to 'smoothed': Newton reuses one ML over many solves, where fewer "
      "iterations pay more.");
    if (with_rebuild)
      prm.declare_entry("AMG rebuild iterations",
                        std::to_string(amg_rebuild_iterations),
                        Patterns::Integer(1),
                        "With 'cg amg' or 'gmres amg': when a linear solve "
                        "takes more iterations than this, ML is rebuilt on "
                        "the current tangent for the following solves; a "
                        "solve still running at twice this many is "
                        "continued with ML rebuilt at once.");
  }

  void
  LinearSolver::Parameters::parse_tuning_parameters(ParameterHandler &prm,
                                                    const bool with_rebuild)
  {
    gmres_restart             = prm.get_integer("GMRES restart");
    amg_smoother_sweeps       = prm.get_integer("AMG smoother sweeps");
    amg_aggregation_threshold = prm.get_double("AMG aggregation threshold");
    amg_smoothed_aggregation  = prm.get("AMG prolongator") == "smoothed";
    if (with_rebuild)
      amg_rebuild_iterations = prm.get_integer("AMG rebuild iterations");
  }

  void
  LinearSolver::initialize(const Parameters                &parameters,
                           const std::vector<Point<3>>     &points,
                           const std::vector<unsigned int> &component)
  {
    AssertThrow(
      parameters.method == "gmres jacobi" || parameters.method == "cg amg" ||
        parameters.method == "gmres amg" || parameters.method == "direct",
      ExcMessage("Unknown linear solver '" + parameters.method + "'."));
    prm           = parameters;
    dof_points    = points;
    dof_component = component;
    matrix        = nullptr;
    amg.clear();
    amg_matrix.clear();
    amg_built = false;
    cholesky.clear();
    amg_builds = factorizations = 0;
  }

  void
  LinearSolver::scene_dof_points(const Scene               &scene,
                                 std::vector<Point<3>>     &points,
                                 std::vector<unsigned int> &component)
  {
    const unsigned int n = scene.n_dofs();
    points.assign(n, Point<3>());
    component.assign(n, numbers::invalid_unsigned_int);
    for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
      if (scene.vertex_dofs()[v][0] != numbers::invalid_dof_index)
        for (unsigned int c = 0; c < 3; ++c)
          {
            points[scene.vertex_dofs()[v][c]]    = scene.vertices()[v];
            component[scene.vertex_dofs()[v][c]] = c;
          }
  }

  void
  LinearSolver::initialize(const Parameters &parameters, const Scene &scene)
  {
    std::vector<Point<3>>     points;
    std::vector<unsigned int> component;
    scene_dof_points(scene, points, component);
    initialize(parameters, points, component);
  }

  bool
  LinearSolver::set_matrix(const SparseMatrix<double> &new_matrix)
  {
    matrix = &new_matrix;
    if (prm.method == "gmres jacobi")
      jacobi.initialize(new_matrix);
    else if (prm.method == "direct")
      {
        ++factorizations;
        return cholesky.refactorize(new_matrix);
      }
    else if (!amg_built)
      build_amg(new_matrix);
    return true;
  }

  void
  LinearSolver::build_amg(const SparseMatrix<double> &source)
  {
    // A rebuild frees the old hierarchy and matrix first: deal.II builds
    // the new ML before it lets go of the old one, which held two
    // hierarchies at once (the serial reference at 584k peaked 3.9 GB
    // above its trend after one rebuild).
    amg.clear();
    amg_matrix.clear();
    amg_matrix.reinit(source);
    const unsigned int n = dof_points.size();
    AssertDimension(source.m(), n);
    // Rotations are taken about the centroid to keep the modes balanced.
    Point<3> centroid;
    for (const auto &p : dof_points)
      centroid += p;
    centroid /= std::max(n, 1u);
    Teuchos::ParameterList parameters;
    const auto             null_space = amg_parameters(
      prm, amg_matrix, dof_points, dof_component, centroid, parameters);
    amg.initialize(amg_matrix, parameters);
    amg_built = true;
    ++amg_builds;
  }

  std::array<std::unique_ptr<Epetra_MultiVector>, 2>
  LinearSolver::amg_parameters(const Parameters                     &prm,
                               const TrilinosWrappers::SparseMatrix &matrix,
                               const std::vector<Point<3>>          &points,
                               const std::vector<unsigned int>      &component,
                               const Point<3>                       &centroid,
                               Teuchos::ParameterList               &parameters)
  {
    const unsigned int                                n = points.size();
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.higher_order_elements = false;
    data.smoother_sweeps       = prm.amg_smoother_sweeps;
    data.aggregation_threshold = prm.amg_aggregation_threshold;
    data.constant_modes =
      std::vector<std::vector<bool>>(3, std::vector<bool>(n, false));
    for (unsigned int i = 0; i < n; ++i)
      if (component[i] < 3)
        data.constant_modes[component[i]][i] = true;

    std::array<std::unique_ptr<Epetra_MultiVector>, 2> vectors;
    data.set_parameters(parameters, vectors[0], matrix);

    // Elasticity needs the three rotations besides the translations, or the
    // iteration count grows with the mesh.
    vectors[1] =
      std::make_unique<Epetra_MultiVector>(matrix.trilinos_matrix().DomainMap(),
                                           6);
    Epetra_MultiVector &modes = *vectors[1];
    // Aggregate points (blocks of three DoFs), not single DoFs, when the
    // DoFs of every point are 3k..3k+2: this made ML's setup about 25%
    // cheaper on the 100k cube for about the same number of CG iterations.
    bool point_blocks = (n % 3 == 0);
    for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int c = component[i];
        if (c >= 3)
          continue;
        if (c != i % 3 || points[i] != points[i - i % 3])
          point_blocks = false;
        const Tensor<1, 3> x = points[i] - centroid;
        modes[c][i]          = 1.;
        // rotation about e_k: e_k x x, component c
        const unsigned int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        modes[3 + c1][i] = x[c2];  // (e_c1 x x)_c = x_c2
        modes[3 + c2][i] = -x[c1]; // (e_c2 x x)_c = -x_c1
      }
    // Every process must agree (a distributed matrix's owned ranges hold
    // whole points, so they do).
    point_blocks = Utilities::MPI::min(static_cast<unsigned int>(point_blocks),
                                       matrix.get_mpi_communicator()) == 1;
    parameters.set("PDE equations", point_blocks ? 3 : 1);
    parameters.set("null space: type", "pre-computed");
    parameters.set("null space: dimension", modes.NumVectors());
    parameters.set("null space: vectors", modes.Values());
    // Unsmoothed aggregates: the prolongator smoothing (two sparse matrix
    // products per level) was most of ML's setup; uncoupled aggregation
    // (no MIS on the coarse levels) was 10 % cheaper for the same
    // iterations on one process. 'smoothed' keeps ML's defaults.
    if (!prm.amg_smoothed_aggregation)
      {
        parameters.set("aggregation: type", "Uncoupled");
        parameters.set("aggregation: damping factor", 0.);
      }
    return vectors;
  }

  bool
  LinearSolver::iterate(const Vector<double> &rhs,
                        Vector<double>       &solution,
                        const unsigned int    limit,
                        Result               &result)
  {
    SolverControl control(limit,
                          prm.relative_tolerance * rhs.l2_norm(),
                          false,
                          false);
    bool          converged = true;
    try
      {
        if (prm.method == "cg amg")
          {
            // A step length alpha <= 0 means p^T A p <= 0. The signal
            // reports alpha one iteration late; the next check stops CG.
            SolverCG<Vector<double>> cg(control);
            cg.connect_coefficients_slot([&](const double alpha, const double) {
              if (!(alpha > 0.))
                result.negative_curvature = true;
            });
            cg.connect(
              [&](const unsigned int, const double, const Vector<double> &) {
                return result.negative_curvature ? SolverControl::failure :
                                                   SolverControl::success;
              });
            cg.solve(*matrix, solution, rhs, amg);
          }
        else
          {
            SolverGMRES<Vector<double>> gmres(
              control,
              SolverGMRES<Vector<double>>::AdditionalData(prm.gmres_restart +
                                                          2));
            if (prm.method == "gmres amg")
              gmres.solve(*matrix, solution, rhs, amg);
            else
              gmres.solve(*matrix, solution, rhs, jacobi);
          }
      }
    catch (const std::exception &)
      {
        converged = false;
      }
    result.iterations += control.last_step();
    result.relative_residual =
      control.last_value() / std::max(rhs.l2_norm(), 1e-300);
    return converged;
  }

  LinearSolver::Result
  LinearSolver::solve(const Vector<double> &rhs, Vector<double> &solution)
  {
    Assert(matrix != nullptr, ExcMessage("LinearSolver::set_matrix() first."));
    Result result;
    if (prm.method == "direct")
      {
        cholesky.solve(rhs, solution);
        result.converged  = true;
        result.iterations = 1;
        return result;
      }
    if (prm.amg_rebuild_iterations == 0 || prm.method == "gmres jacobi")
      {
        result.converged = iterate(rhs, solution, prm.max_iterations, result);
        return result;
      }

    // ML built on an earlier matrix (the stiffness at rest) loses its grip
    // far from it: continue a slow solve with ML rebuilt on this matrix,
    // and rebuild it for the next ones after a solve over the limit.
    const unsigned int first_attempt =
      std::min(prm.max_iterations, 2 * prm.amg_rebuild_iterations);
    result.converged = iterate(rhs, solution, first_attempt, result);
    if (!result.converged && !result.negative_curvature &&
        first_attempt < prm.max_iterations)
      {
        build_amg(*matrix);
        result.converged =
          iterate(rhs, solution, prm.max_iterations - first_attempt, result);
      }
    else if (result.iterations > prm.amg_rebuild_iterations)
      build_amg(*matrix);
    return result;
  }

  const LinearSolver::Parameters &
  LinearSolver::parameters() const
  {
    return prm;
  }

  unsigned int
  LinearSolver::n_amg_builds() const
  {
    return amg_builds;
  }

  unsigned int
  LinearSolver::n_factorizations() const
  {
    return factorizations;
  }
} // namespace softface

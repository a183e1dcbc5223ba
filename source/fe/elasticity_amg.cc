#include <softface/fe/elasticity_amg.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

namespace softface
{
  void
  initialize_elasticity_amg(const Scene                          &scene,
                            const TrilinosWrappers::SparseMatrix &matrix,
                            const double       aggregation_threshold,
                            const unsigned int smoother_sweeps,
                            TrilinosWrappers::PreconditionAMG &amg)
  {
    std::vector<Point<3>>     points(scene.dof_handler.n_dofs());
    std::vector<unsigned int> component(scene.dof_handler.n_dofs(),
                                        numbers::invalid_unsigned_int);
    for (unsigned int v = 0; v < scene.vertex_dofs().size(); ++v)
      if (scene.vertex_dofs()[v][0] != numbers::invalid_dof_index)
        for (unsigned int c = 0; c < 3; ++c)
          {
            points[scene.vertex_dofs()[v][c]]    = scene.triangulation.get_vertices()[v];
            component[scene.vertex_dofs()[v][c]] = c;
          }
    initialize_elasticity_amg(
      points, component, matrix, aggregation_threshold, smoother_sweeps, amg);
  }

  void
  initialize_elasticity_amg(const std::vector<Point<3>>          &dof_points,
                            const std::vector<unsigned int>      &dof_component,
                            const TrilinosWrappers::SparseMatrix &matrix,
                            const double       aggregation_threshold,
                            const unsigned int smoother_sweeps,
                            TrilinosWrappers::PreconditionAMG &amg)
  {
    const unsigned int n = dof_points.size();
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.higher_order_elements = false;
    data.smoother_sweeps       = smoother_sweeps;
    data.aggregation_threshold = aggregation_threshold;
    data.constant_modes =
      std::vector<std::vector<bool>>(3, std::vector<bool>(n, false));
    for (unsigned int i = 0; i < n; ++i)
      if (dof_component[i] < 3)
        data.constant_modes[dof_component[i]][i] = true;

    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> translations;
    data.set_parameters(parameters, translations, matrix);

    // deal.II 9.4 hands ML only the three translations; elasticity needs
    // the three rotations too, or the iteration count grows with the mesh.
    // Rotations are taken about the centroid to keep the modes balanced.
    Epetra_MultiVector modes(matrix.trilinos_matrix().DomainMap(), 6);
    Point<3>           centroid;
    for (const auto &p : dof_points)
      centroid += p;
    centroid /= std::max(n, 1u);
    // Aggregate points (blocks of three DoFs), not single DoFs, when the
    // DoFs of every point are 3k..3k+2: this made ML's setup about 25%
    // cheaper on the 100k cube for about the same number of CG iterations.
    bool point_blocks = (n % 3 == 0);
    for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int c = dof_component[i];
        if (c >= 3)
          continue;
        if (c != i % 3 || dof_points[i] != dof_points[i - i % 3])
          point_blocks = false;
        const Tensor<1, 3> x = dof_points[i] - centroid;
        modes[c][i]          = 1.;
        // rotation about e_k: e_k x x, component c
        const unsigned int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        modes[3 + c1][i] = x[c2];  // (e_c1 x x)_c = x_c2
        modes[3 + c2][i] = -x[c1]; // (e_c2 x x)_c = -x_c1
      }
    parameters.set("PDE equations", point_blocks ? 3 : 1);
    parameters.set("null space: type", "pre-computed");
    parameters.set("null space: dimension", modes.NumVectors());
    parameters.set("null space: vectors", modes.Values());

    amg.initialize(matrix, parameters);
  }
} // namespace softface

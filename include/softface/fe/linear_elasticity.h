#ifndef softface_linear_elasticity_h
#define softface_linear_elasticity_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <softface/core/scene.h>

#include <array>
#include <cstdint>

namespace softface
{
  using namespace dealii;

  /**
   * Linear elasticity on P1 tetrahedra (seed 2.1 and eqs. 6-10). On a P1
   * tetrahedron the shape gradients are constant, so the element stiffness
   * has a closed form; it is the same matrix that FEValues with a one-point
   * QGaussSimplex would integrate (a test checks that), at a fraction of the
   * cost. The mass tensor model reads the same 3x3 blocks.
   */
  namespace LinearElasticity
  {
    /// K[a][b]: the 3x3 block coupling vertex a's force to vertex b's
    /// displacement (Cotin's K_ab^T, seed eq. 8).
    using TetrahedronStiffness = std::array<std::array<Tensor<2, 3>, 4>, 4>;

    TetrahedronStiffness
    tetrahedron_stiffness(const std::array<Point<3>, 4> &vertices,
                          const double                   lambda,
                          const double                   mu);

    /// The vertices of a cell in deal.II's order.
    std::array<Point<3>, 4>
    cell_vertices(const Triangulation<3>::active_cell_iterator &cell);

    /// Sparsity of the scene's DoF layout (all vertex couplings).
    void
    make_sparsity_pattern(const Scene &scene, SparsityPattern &sparsity);

    /// Add a 12x12 cell matrix (blocks K[a][b]) at the DoFs of its vertices.
    void
    add_cell_matrix(const std::array<types::global_dof_index, 12> &dofs,
                    const TetrahedronStiffness                    &K,
                    SparseMatrix<double>                          &matrix);

    /// The local indices 0..11 ordered by their DoF.
    std::array<std::uint8_t, 12>
    sorted_order(const std::array<types::global_dof_index, 12> &dofs);

    /// The same, with the order precomputed (sorted_order(dofs)).
    void
    add_cell_matrix(const std::array<types::global_dof_index, 12> &dofs,
                    const std::array<std::uint8_t, 12>            &order,
                    const TetrahedronStiffness                    &K,
                    SparseMatrix<double>                          &matrix);

    /**
     * Eliminate the join DoFs symmetrically: zero their rows and columns,
     * keep the diagonal. The matrix stays SPD if it was, and no longer
     * depends on where the join points move.
     */
    void
    eliminate_join_dofs(const std::vector<bool> &is_join,
                        SparseMatrix<double>    &matrix);

    /// The unconstrained global stiffness matrix (sparsity already set).
    void
    assemble_stiffness(const Scene &scene, SparseMatrix<double> &stiffness);
  } // namespace LinearElasticity
} // namespace softface

#endif

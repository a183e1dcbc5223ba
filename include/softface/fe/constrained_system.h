#ifndef softface_fe_constrained_system_h
#define softface_fe_constrained_system_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/fe/elasticity.h>

#include <array>
#include <cstdint>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * Linear systems whose join DoFs are prescribed (Mollemans et al. 2007,
   * Sec. 3.3), as the FEM models and the mass tensor model's converged answer
   * build them: the sparsity of the shared layout, cell matrices added row by
   * row, and the symmetric elimination of the join DoFs, which keeps an SPD
   * matrix SPD and independent of where the join points move.
   */
  namespace ConstrainedSystem
  {
    /// Sparsity of the scene's DoF layout (all vertex couplings), with the
    /// fill its vertex constraints need when condensed.
    void
    make_sparsity_pattern(const Scene &scene, SparsityPattern &sparsity);

    /// The twelve DoFs of a cell on the shared layout (vertex by vertex).
    std::array<types::global_dof_index, 12>
    cell_dofs(const Scene                                  &scene,
              const Triangulation<3>::active_cell_iterator &cell);

    /// The local indices 0..11 ordered by their DoF.
    std::array<std::uint8_t, 12>
    sorted_order(const std::array<types::global_dof_index, 12> &dofs);

    /// Add a 12x12 cell matrix (blocks K[a][b]) at the DoFs of its vertices.
    void
    add_cell_matrix(const std::array<types::global_dof_index, 12> &dofs,
                    const Elasticity::CellMatrix                  &K,
                    SparseMatrix<double>                          &matrix);

    /// The same, with the order precomputed (sorted_order(dofs)), adding
    /// only the rows in [@p first_row, @p end_row) (a RowPartition's part).
    void
    add_cell_matrix(
      const std::array<types::global_dof_index, 12> &dofs,
      const std::array<std::uint8_t, 12>            &order,
      const Elasticity::CellMatrix                  &K,
      SparseMatrix<double>                          &matrix,
      types::global_dof_index                        first_row = 0,
      types::global_dof_index end_row = numbers::invalid_dof_index);

    /**
     * Eliminate the join DoFs symmetrically: zero their rows and columns,
     * keep the diagonal's magnitude (1 where it is zero), so that the matrix
     * is positive definite exactly when its free block is.
     */
    void
    eliminate_join_dofs(const std::vector<bool> &is_join,
                        SparseMatrix<double>    &matrix);

    /**
     * The right-hand side that goes with the eliminated matrix when the join
     * DoFs move by @p join_values (read on join DoFs only) and the residual
     * force is @p residual (null: zero): -(K d + r) on the free rows,
     * |K_jj| d_j on the join rows. @p unconstrained is K before elimination;
     * its diagonal's magnitude is the eliminated matrix's.
     */
    void
    right_hand_side(const SparseMatrix<double> &unconstrained,
                    const std::vector<bool>    &is_join,
                    const Vector<double>       &join_values,
                    const Vector<double>       *residual,
                    Vector<double>             &rhs);

    /// The Euclidean norm of @p v over the free DoFs.
    double
    free_norm(const std::vector<bool> &is_join, const Vector<double> &v);
  } // namespace ConstrainedSystem
} // namespace softface

#endif

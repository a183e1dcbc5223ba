// Linear systems with prescribed join DoFs (fe): sparsity of the shared
// layout, cell matrices added row by row, symmetric elimination of the join
// DoFs and the right-hand side that goes with it. Used by linear FEM, the
// nonlinear models' Newton iterations and the mass tensor model.

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <softface/core/threads.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/vertex_constraints.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace softface
{
  namespace ConstrainedSystem
  {
    void
    make_sparsity_pattern(const Scene &scene, SparsityPattern &sparsity)
    {
      DynamicSparsityPattern dsp(scene.dof_handler.n_dofs());
      DoFTools::make_sparsity_pattern(scene.dof_handler, dsp);
      // Constraints between the two sides of a slit couple each side's
      // vertex with the other's neighbours once condensed.
      if (scene.has_vertex_constraints())
        VertexConstraintSet(scene).add_fill(dsp);
      sparsity.copy_from(dsp);
    }

    std::array<types::global_dof_index, 12>
    cell_dofs(const Scene                                  &scene,
              const Triangulation<3>::active_cell_iterator &cell)
    {
      std::array<types::global_dof_index, 12> dofs;
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int i = 0; i < 3; ++i)
          dofs[3 * a + i] = scene.vertex_dofs()[cell->vertex_index(a)][i];
      return dofs;
    }

    std::array<std::uint8_t, 12>
    sorted_order(const std::array<types::global_dof_index, 12> &dofs)
    {
      std::array<std::uint8_t, 12> order;
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(),
                order.end(),
                [&](unsigned int p, unsigned int q) {
                  return dofs[p] < dofs[q];
                });
      return order;
    }

    void
    add_cell_matrix(const std::array<types::global_dof_index, 12> &dofs,
                    const Elasticity::CellMatrix                  &K,
                    SparseMatrix<double>                          &matrix)
    {
      add_cell_matrix(dofs, sorted_order(dofs), K, matrix);
    }

    void
    add_cell_matrix(const std::array<types::global_dof_index, 12> &dofs,
                    const std::array<std::uint8_t, 12>            &order,
                    const Elasticity::CellMatrix                  &K,
                    SparseMatrix<double>                          &matrix,
                    const types::global_dof_index                  first_row,
                    const types::global_dof_index                  end_row)
    {
      // Adding a row with sorted column indices lets SparseMatrix merge it
      // into the row instead of searching for each entry: one order serves
      // all twelve rows (and, precomputed, every assembly).
      std::array<types::global_dof_index, 12> sorted_dofs;
      std::array<double, 12>                  row_values;
      for (unsigned int k = 0; k < 12; ++k)
        sorted_dofs[k] = dofs[order[k]];
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int i = 0; i < 3; ++i)
          {
            if (dofs[3 * a + i] < first_row || dofs[3 * a + i] >= end_row)
              continue;
            for (unsigned int k = 0; k < 12; ++k)
              row_values[k] = K[a][order[k] / 3][i][order[k] % 3];
            matrix.add(dofs[3 * a + i],
                       12,
                       sorted_dofs.data(),
                       row_values.data(),
                       /*elide_zero_values=*/false,
                       /*col_indices_are_sorted=*/true);
          }
    }

    void
    eliminate_join_dofs(const std::vector<bool> &is_join,
                        SparseMatrix<double>    &matrix)
    {
      // Rows in ranges on the threads (Newton eliminates on every tangent):
      // every entry is set on its own, so the matrix is the same on any
      // number of threads.
      const unsigned int n_rows  = matrix.m();
      const unsigned int n_tasks = std::min(n_rows, 8 * Threads::n_threads());
      Threads::run_tasks(n_tasks, [&](const unsigned int task) {
        const unsigned int begin = std::uint64_t(n_rows) * task / n_tasks;
        const unsigned int end   = std::uint64_t(n_rows) * (task + 1) / n_tasks;
        for (unsigned int row = begin; row < end; ++row)
          {
            for (auto entry = matrix.begin(row); entry != matrix.end(row);
                 ++entry)
              if ((is_join[row] || is_join[entry->column()]) &&
                  entry->column() != row)
                entry->value() = 0.;
            // A join DoF keeps the size of its diagonal entry (the solvers'
            // scaling) but not its sign: under strong compression it can be
            // negative, and the matrix must be positive definite exactly
            // when its free block is. 1 for a join DoF whose cells were all
            // left out (see right_hand_side).
            if (is_join[row])
              {
                double &diagonal = matrix.diag_element(row);
                diagonal         = diagonal != 0. ? std::abs(diagonal) : 1.;
              }
          }
      });
    }

    void
    right_hand_side(const SparseMatrix<double> &unconstrained,
                    const std::vector<bool>    &is_join,
                    const Vector<double>       &join_values,
                    const Vector<double>       *residual,
                    Vector<double>             &rhs)
    {
      const unsigned int n = is_join.size();
      Vector<double>     d(n);
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          d[i] = join_values[i];
      rhs.reinit(n);
      unconstrained.vmult(rhs, d);
      if (residual != nullptr)
        rhs += *residual;
      rhs *= -1.;
      for (unsigned int i = 0; i < n; ++i)
        if (is_join[i])
          rhs[i] = (unconstrained.diag_element(i) != 0. ?
                      std::abs(unconstrained.diag_element(i)) :
                      1.) *
                   d[i];
    }

    double
    free_norm(const std::vector<bool> &is_join, const Vector<double> &v)
    {
      double sum = 0.;
      for (unsigned int i = 0; i < v.size(); ++i)
        if (!is_join[i])
          sum += v[i] * v[i];
      return std::sqrt(sum);
    }
  } // namespace ConstrainedSystem
} // namespace softface

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>

#include <softface/fe/linear_elasticity.h>

#include <algorithm>
#include <numeric>

namespace softface
{
  namespace LinearElasticity
  {
    TetrahedronStiffness
    tetrahedron_stiffness(const std::array<Point<3>, 4> &x,
                          const double                   lambda,
                          const double                   mu)
    {
      // The columns of J are the edges from vertex 0; the rows of J^-1 are
      // the (constant) gradients of the barycentric shape functions 1..3.
      Tensor<2, 3> J;
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int d = 0; d < 3; ++d)
          J[d][k] = x[k + 1][d] - x[0][d];
      const double       volume    = determinant(J) / 6.;
      const Tensor<2, 3> J_inverse = invert(J);

      std::array<Tensor<1, 3>, 4> grad;
      for (unsigned int a = 1; a < 4; ++a)
        grad[a] = J_inverse[a - 1];
      grad[0] = -(grad[1] + grad[2] + grad[3]);

      // Second derivative of the elastic energy
      //   V (lambda/2 (div u)^2 + mu eps:eps)
      // with respect to u_a[i] and u_b[j].
      TetrahedronStiffness K;
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int b = 0; b < 4; ++b)
          {
            const double shear = mu * (grad[a] * grad[b]);
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int j = 0; j < 3; ++j)
                K[a][b][i][j] = volume * (lambda * grad[a][i] * grad[b][j] +
                                          mu * grad[a][j] * grad[b][i] +
                                          (i == j ? shear : 0.));
          }
      return K;
    }

    std::array<Point<3>, 4>
    cell_vertices(const Triangulation<3>::active_cell_iterator &cell)
    {
      return {
        {cell->vertex(0), cell->vertex(1), cell->vertex(2), cell->vertex(3)}};
    }

    void
    make_sparsity_pattern(const Scene &scene, SparsityPattern &sparsity)
    {
      DynamicSparsityPattern dsp(scene.dof_handler.n_dofs());
      DoFTools::make_sparsity_pattern(scene.dof_handler, dsp);
      sparsity.copy_from(dsp);
    }

    void
    assemble_stiffness(const Scene &scene, SparseMatrix<double> &stiffness)
    {
      const double lambda = scene.material.lambda();
      const double mu     = scene.material.mu();

      std::array<types::global_dof_index, 12> dofs;
      stiffness = 0;
      for (const auto &cell : scene.triangulation.active_cell_iterators())
        {
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              dofs[3 * a + i] = scene.vertex_dofs()[cell->vertex_index(a)][i];
          add_cell_matrix(dofs,
                          tetrahedron_stiffness(cell_vertices(cell),
                                                lambda,
                                                mu),
                          stiffness);
        }
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
                    const TetrahedronStiffness                    &K,
                    SparseMatrix<double>                          &matrix)
    {
      add_cell_matrix(dofs, sorted_order(dofs), K, matrix);
    }

    void
    add_cell_matrix(const std::array<types::global_dof_index, 12> &dofs,
                    const std::array<std::uint8_t, 12>            &order,
                    const TetrahedronStiffness                    &K,
                    SparseMatrix<double>                          &matrix)
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
      for (unsigned int row = 0; row < matrix.m(); ++row)
        for (auto entry = matrix.begin(row); entry != matrix.end(row); ++entry)
          if ((is_join[row] || is_join[entry->column()]) &&
              entry->column() != row)
            entry->value() = 0.;
    }
  } // namespace LinearElasticity
} // namespace softface

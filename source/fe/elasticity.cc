// Elasticity kernels (fe): the P1 closed forms (forces, tangent, the linear
// stiffness that linear FEM and the mass tensor model share) and assembly by
// quadrature on any element (the quadratic reference), all contracting the
// one material law of fe/material_law.cc.

#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <softface/core/threads.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/point_block_pattern.h>
#include <softface/fe/row_partition.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

namespace softface
{
  namespace Elasticity
  {
    void
    p1_tangent(const Tetrahedron::Geometry &tetrahedron,
               const Tensor<4, 3>          &A,
               CellMatrix                  &K)
    {
      // This runs once per cell and Newton iteration, so it does as little
      // as the algebra allows. The gradients sum to zero, so every block row
      // and column does too: K_a0 = -(K_a1 + K_a2 + K_a3). Only
      // G_a = V grad_a[J] A[.][J][.][.] for a = 1..3 and the blocks K_ab,
      // 1 <= a <= b <= 3, are products; the rest are sums and transposes.
      double g[4][3];
      for (unsigned int a = 1; a < 4; ++a)
        for (unsigned int J = 0; J < 3; ++J)
          g[a][J] = tetrahedron.gradients[a][J];
      double G[4][3][3][3];
      for (unsigned int a = 1; a < 4; ++a)
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int L = 0; L < 3; ++L)
              G[a][i][k][L] = tetrahedron.volume * (g[a][0] * A[i][0][k][L] +
                                                    g[a][1] * A[i][1][k][L] +
                                                    g[a][2] * A[i][2][k][L]);
      for (unsigned int a = 1; a < 4; ++a)
        for (unsigned int b = a; b < 4; ++b)
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int k = 0; k < 3; ++k)
              {
                const double value = G[a][i][k][0] * g[b][0] +
                                     G[a][i][k][1] * g[b][1] +
                                     G[a][i][k][2] * g[b][2];
                K[a][b][i][k] = value;
                K[b][a][k][i] = value;
              }
      for (unsigned int a = 1; a < 4; ++a)
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int k = 0; k < 3; ++k)
            {
              const double value =
                -(K[a][1][i][k] + K[a][2][i][k] + K[a][3][i][k]);
              K[a][0][i][k] = value;
              K[0][a][k][i] = value;
            }
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int k = 0; k < 3; ++k)
          K[0][0][i][k] = -(K[0][1][i][k] + K[0][2][i][k] + K[0][3][i][k]);
    }

    Tensor<4, 3>
    linear_tangent(const Lame &lame)
    {
      Tensor<2, 3> P;
      Tensor<4, 3> A;
      MaterialLaw::first_piola_kirchhoff(
        MaterialLaw::Law::linear, lame, unit_symmetric_tensor<3>(), P, &A);
      return A;
    }

    CellMatrix
    p1_stiffness(const Tetrahedron::Geometry &tetrahedron,
                 const Tensor<4, 3>          &linear_tangent)
    {
      CellMatrix K;
      p1_tangent(tetrahedron, linear_tangent, K);
      return K;
    }

    bool
    p1_response(const MaterialLaw::Law             law,
                const Lame                        &lame,
                const Tetrahedron::Geometry       &tetrahedron,
                const std::array<Tensor<1, 3>, 4> &u,
                const bool                         with_tangent,
                P1Response                        &response)
    {
      Tensor<2, 3> F = unit_symmetric_tensor<3>();
      for (unsigned int a = 0; a < 4; ++a)
        F += outer_product(u[a], tetrahedron.gradients[a]);
      Tensor<2, 3> P;
      Tensor<4, 3> A;
      if (!MaterialLaw::first_piola_kirchhoff(
            law, lame, F, P, with_tangent ? &A : nullptr))
        return false;
      for (unsigned int a = 0; a < 4; ++a)
        response.force[a] = tetrahedron.volume * (P * tetrahedron.gradients[a]);
      if (with_tangent)
        p1_tangent(tetrahedron, A, response.tangent);
      return true;
    }

    void
    assemble_p1_stiffness(const Scene             &scene,
                          const SparsityPattern   &sparsity,
                          SparseMatrix<double>    &stiffness,
                          const PointBlockPattern *pattern)
    {
      // Entries go straight into the value array: the sparsity must be the
      // pattern's.
      AssertThrow(pattern == nullptr ||
                    sparsity.n_nonzero_elements() == pattern->n_entries(),
                  ExcMessage("The sparsity is not the PointBlockPattern's."));
      // One tangent per tissue (one without heterogeneous tissue).
      std::vector<Tensor<4, 3>> A;
      for (unsigned int t = 0; t < scene.n_tissues(); ++t)
        A.push_back(linear_tangent(scene.tissue(t).lame()));
      // The matrix's allocation (deal.II zero-fills a new value array on
      // one thread: 0.05-0.08 s for the 115 MB of a 491k mesh) and the
      // cells' DoFs with the rows' split are apart: on two threads they run
      // side by side. reinit() leaves every entry zero.
      std::vector<Triangulation<3>::active_cell_iterator>  cells;
      std::vector<std::array<types::global_dof_index, 12>> dofs;
      RowPartition                                         partition;
      Threads::run_tasks(2, [&](const unsigned int task) {
        if (task == 0)
          {
            stiffness.reinit(sparsity);
            return;
          }
        cells.reserve(scene.triangulation.n_active_cells());
        dofs.reserve(scene.triangulation.n_active_cells());
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          {
            cells.push_back(cell);
            dofs.push_back(ConstrainedSystem::cell_dofs(scene, cell));
          }
        partition.reinit(dofs, sparsity.n_rows(), Threads::n_threads());
      });
      // A square matrix stores the diagonal first in each row, so entry
      // (0,0) starts its value array.
      double *const values =
        stiffness.m() > 0 ? &stiffness.diag_element(0) : nullptr;
      Threads::run_tasks(partition.n_parts(), [&](const unsigned int p) {
        const auto                    first = partition.first_row_of(p);
        const auto                    end   = partition.first_row_of(p + 1);
        std::array<unsigned int, 144> positions;
        for (const unsigned int c : partition.cells(p))
          {
            const CellMatrix K =
              p1_stiffness(Tetrahedron::geometry(
                             Tetrahedron::vertices(cells[c])),
                           A[scene.tissue_of_cell(c)]);
            if (pattern == nullptr)
              {
                ConstrainedSystem::add_cell_matrix(
                  dofs[c],
                  ConstrainedSystem::sorted_order(dofs[c]),
                  K,
                  stiffness,
                  first,
                  end);
                continue;
              }
            pattern->cell_positions(c, positions.data());
            for (unsigned int r = 0; r < 12; ++r)
              {
                if (dofs[c][r] < first || dofs[c][r] >= end)
                  continue;
                const unsigned int *position = &positions[12 * r];
                for (unsigned int b = 0; b < 4; ++b)
                  for (unsigned int j = 0; j < 3; ++j)
                    values[*position++] += K[r / 3][b][r % 3][j];
              }
          }
      });
    }

    void
    assemble_body_force(
      const Mapping<3>                                       &mapping,
      const Quadrature<3>                                    &quadrature,
      const SceneEffects                                     &effects,
      const std::vector<DoFHandler<3>::active_cell_iterator> &cells,
      const IndexSet                                         &dofs,
      Vector<double>                                         &forces)
    {
      if (cells.empty())
        return;
      const FiniteElement<3>              &fe = cells.front()->get_fe();
      FEValues<3>                          fe_values(mapping,
                            fe,
                            quadrature,
                            update_values | update_JxW_values);
      std::vector<types::global_dof_index> cell_dofs(fe.n_dofs_per_cell());
      for (const auto &cell : cells)
        {
          fe_values.reinit(cell);
          cell->get_dof_indices(cell_dofs);
          const Tensor<1, 3> b = effects.body_force_per_unit_volume(cell);
          for (unsigned int i = 0; i < cell_dofs.size(); ++i)
            if (dofs.is_element(cell_dofs[i]))
              {
                const unsigned int c = fe.system_to_component_index(i).first;
                for (unsigned int q = 0; q < quadrature.size(); ++q)
                  forces[cell_dofs[i]] +=
                    b[c] * fe_values.shape_value(i, q) * fe_values.JxW(q);
              }
        }
    }

    bool
    cell_response(const MaterialLaw::Law           law,
                  const Lame                      &lame,
                  const FEValues<3>               &fe_values,
                  const std::vector<unsigned int> &component,
                  const std::vector<double>       &u_cell,
                  Vector<double>                  &f_cell,
                  FullMatrix<double>              *K_cell)
    {
      const unsigned int n = u_cell.size();
      // Up to quadratic tetrahedra (30 DoFs) without an allocation per
      // cell; larger elements allocate.
      std::array<Tensor<1, 3>, 30> grad_small;
      std::vector<Tensor<1, 3>>    grad_large(n > 30 ? n : 0);
      Tensor<1, 3> *const grad = n > 30 ? grad_large.data() : grad_small.data();
      Tensor<2, 3>        P;
      Tensor<4, 3>        A;
      f_cell = 0;
      if (K_cell != nullptr)
        *K_cell = 0;
      for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
        {
          Tensor<2, 3> F = unit_symmetric_tensor<3>();
          for (unsigned int i = 0; i < n; ++i)
            {
              grad[i] = fe_values.shape_grad(i, q);
              F[component[i]] += u_cell[i] * grad[i];
            }
          if (!MaterialLaw::first_piola_kirchhoff(
                law, lame, F, P, K_cell != nullptr ? &A : nullptr))
            return false;
          const double JxW = fe_values.JxW(q);
          for (unsigned int i = 0; i < n; ++i)
            f_cell[i] += (P[component[i]] * grad[i]) * JxW;
          if (K_cell == nullptr)
            continue;
          // K_ij = grad_i . A[c_i][.][c_j][.] . grad_j, contracted with
          // grad_i first so that the inner loop is three products.
          for (unsigned int i = 0; i < n; ++i)
            {
              Tensor<2, 3> G; // G[k][L] = grad_i[J] A[c_i][J][k][L]
              for (unsigned int J = 0; J < 3; ++J)
                G += grad[i][J] * A[component[i]][J];
              G *= JxW;
              for (unsigned int j = 0; j < n; ++j)
                (*K_cell)(i, j) += G[component[j]] * grad[j];
            }
        }
      return true;
    }

    bool
    assemble(const MaterialLaw::Law            law,
             const std::vector<Lame>          &tissue_lame,
             const std::vector<unsigned char> &tissue_of_cell,
             const Mapping<3>                 &mapping,
             const DoFHandler<3>              &dof_handler,
             const Quadrature<3>              &quadrature,
             const Vector<double>             &u,
             Vector<double>                   &forces,
             SparseMatrix<double>             *tangent,
             const std::vector<bool>          *may_skip_cell,
             unsigned int                     *refused_cell)
    {
      const FiniteElement<3>              &fe = dof_handler.get_fe();
      FEValues<3>                          fe_values(mapping,
                            fe,
                            quadrature,
                            update_gradients | update_JxW_values);
      const unsigned int                   n = fe.n_dofs_per_cell();
      std::vector<types::global_dof_index> dofs(n);
      std::vector<unsigned int>            component(n);
      for (unsigned int i = 0; i < n; ++i)
        component[i] = fe.system_to_component_index(i).first;
      std::vector<double> u_cell(n);
      Vector<double>      f_cell(n);
      FullMatrix<double>  K_cell(n, n);
      // Rows go into the matrix with sorted columns: SparseMatrix::add then
      // merges along the row instead of searching it for every entry.
      std::vector<unsigned int>            order(n);
      std::vector<types::global_dof_index> sorted_dofs(n);
      std::vector<double>                  row(n);

      forces.reinit(u.size());
      if (tangent != nullptr)
        *tangent = 0;
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          cell->get_dof_indices(dofs);
          const Lame &lame =
            tissue_lame[tissue_of_cell.empty() ?
                          0 :
                          tissue_of_cell[cell->active_cell_index()]];
          for (unsigned int i = 0; i < n; ++i)
            u_cell[i] = u[dofs[i]];
          if (!cell_response(law,
                             lame,
                             fe_values,
                             component,
                             u_cell,
                             f_cell,
                             tangent != nullptr ? &K_cell : nullptr))
            {
              if (may_skip_cell == nullptr ||
                  !(*may_skip_cell)[cell->active_cell_index()])
                {
                  if (refused_cell != nullptr)
                    *refused_cell = cell->active_cell_index();
                  return false;
                }
              continue;
            }
          for (unsigned int i = 0; i < n; ++i)
            forces[dofs[i]] += f_cell[i];
          if (tangent == nullptr)
            continue;
          std::iota(order.begin(), order.end(), 0u);
          std::sort(order.begin(),
                    order.end(),
                    [&](unsigned int i, unsigned int j) {
                      return dofs[i] < dofs[j];
                    });
          for (unsigned int k = 0; k < n; ++k)
            sorted_dofs[k] = dofs[order[k]];
          for (unsigned int i = 0; i < n; ++i)
            {
              for (unsigned int k = 0; k < n; ++k)
                row[k] = K_cell(i, order[k]);
              tangent->add(
                dofs[i], n, sorted_dofs.data(), row.data(), false, true);
            }
        }
      return true;
    }
  } // namespace Elasticity
} // namespace softface

// The matrix of a rank's own rows filled by the cells at them,
// run by ctest on 2 and 3 ranks (owned_rows_matrix.mpirun=N.output): every
// row a rank owns equals the row of the same matrix assembled on one rank,
// entry for entry and with the same columns, on the cube of Mollemans et al.
// 2007 and the shared gmsh cube. Each cell adds integers made from its serial
// number and its DoFs' serial numbers, so the sums are exact whatever their
// order. Checked with the join DoFs' couplings kept (a Newton tangent), after a
// second assembly (zeroing must leave nothing behind), after the join DoFs
// are eliminated, and with the couplings dropped (the linear FEM
// stiffness). The cells' DoFs as the layout gives them (point blocks: the
// places are found point by point); with the components first (a
// tetrahedron that is no point blocks: places found per entry), so on rank
// 0 only (every rank must then take the general way); and twice
// (24 DoFs, all sums four times as large: added by walking the rows).

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/trilinos_index_access.h>

#include <softface/core/distributed_layout.h>
#include <softface/fe/owned_rows_matrix.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

#include <Epetra_CrsMatrix.h>

#include <cmath>
#include <map>

using namespace softface_tests;

namespace
{
  using JoinCouplings = OwnedRowsMatrix::JoinCouplings;

  // What cell c adds at the serial DoFs (a, b): an integer in [1, 13].
  double
  entry(const unsigned int            c,
        const types::global_dof_index a,
        const types::global_dof_index b)
  {
    return 1. + double((31ull * c + 17ull * a + 7ull * b) % 13);
  }

  // On one rank: the same cells' entries in a deal.II matrix.
  void
  serial_matrix(const Scene          &scene,
                SparsityPattern      &sparsity,
                SparseMatrix<double> &matrix)
  {
    DynamicSparsityPattern dsp(scene.dof_handler.n_dofs());
    DoFTools::make_sparsity_pattern(scene.dof_handler, dsp);
    sparsity.copy_from(dsp);
    matrix.reinit(sparsity);
    std::vector<types::global_dof_index> dofs(12);
    for (const auto &cell : scene.dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < 12; ++i)
          for (unsigned int q = 0; q < 12; ++q)
            matrix.add(dofs[i],
                       dofs[q],
                       entry(cell->active_cell_index(), dofs[i], dofs[q]));
      }
  }

  struct Comparison
  {
    double             largest_difference = 0.;
    unsigned long long wrong_row_lengths  = 0;
    unsigned long long rows               = 0;
  };

  // Every row this rank owns against the serial matrix's: as assembled
  // (@p eliminated false) or after eliminate_join_dofs().
  Comparison
  compare(const DistributedLayout    &layout,
          const OwnedRowsMatrix      &rows,
          const SparsityPattern      &sparsity,
          const SparseMatrix<double> &serial,
          const JoinCouplings         couplings,
          const double                scale,
          const bool                  eliminated,
          const std::vector<double>  &diagonal)
  {
    const auto &is_join = layout.scene.join_dofs();
    const auto &matrix  = rows.matrix().trilinos_matrix();
    Comparison  result;
    for (int r = 0; r < matrix.NumMyRows(); ++r)
      {
        const auto row =
          layout.serial_dof(TrilinosWrappers::global_row_index(matrix, r));
        // The serial row as this matrix must hold it.
        std::map<types::global_dof_index, double> expected;
        for (auto p = sparsity.begin(row); p != sparsity.end(row); ++p)
          {
            const auto column = p->column();
            double     value  = scale * serial(row, column);
            if (is_join[row] && column != row)
              {
                if (couplings == JoinCouplings::dropped)
                  continue;
                if (eliminated)
                  value = 0.;
              }
            else if (is_join[row] && eliminated)
              value = std::abs(value);
            else if (!is_join[row] && is_join[column])
              {
                if (couplings == JoinCouplings::dropped)
                  continue;
                if (eliminated)
                  value = 0.;
              }
            expected[column] = value;
          }
        int     n_entries;
        double *values;
        int    *columns;
        matrix.ExtractMyRowView(r, n_entries, values, columns);
        if (std::size_t(n_entries) != expected.size())
          ++result.wrong_row_lengths;
        for (int k = 0; k < n_entries; ++k)
          {
            const auto column = layout.serial_dof(
              TrilinosWrappers::global_column_index(matrix, columns[k]));
            const auto e = expected.find(column);
            result.largest_difference =
              std::max(result.largest_difference,
                       e == expected.end() ? 1e300 :
                                             std::abs(values[k] - e->second));
          }
        if (eliminated && is_join[row])
          result.largest_difference =
            std::max(result.largest_difference,
                     std::abs(diagonal[r] - expected[row]));
        ++result.rows;
      }
    result.largest_difference =
      Utilities::MPI::max(result.largest_difference, MPI_COMM_WORLD);
    result.wrong_row_lengths =
      Utilities::MPI::sum(result.wrong_row_lengths, MPI_COMM_WORLD);
    result.rows = Utilities::MPI::sum(result.rows, MPI_COMM_WORLD);
    return result;
  }

  void
  check(const std::string &name, const Scene &scene)
  {
    deallog << name << ':' << std::endl;
    SparsityPattern      sparsity;
    SparseMatrix<double> serial;
    serial_matrix(scene, sparsity, serial);

    const DistributedLayout layout(scene, MPI_COMM_WORLD);
    std::vector<char>       relevant_is_join;
    for (const auto dof : layout.locally_relevant_dofs)
      relevant_is_join.push_back(layout.is_join_dof(dof));
    // Every cell at a DoF this rank owns.
    std::vector<DoFHandler<3>::active_cell_iterator> cells;
    std::vector<types::global_dof_index>             cell_dofs;
    layout.cells_at_owned_dofs(cells, cell_dofs);
    std::vector<unsigned int> serial_cell;
    for (const auto &cell : cells)
      serial_cell.push_back(layout.serial_cell(cell)->active_cell_index());

    const bool first_rank =
      Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    for (const std::string order :
         {"", "components first, ", "components first on rank 0, ", "twice, "})
      for (const auto couplings : {JoinCouplings::kept, JoinCouplings::dropped})
        {
          const unsigned int copies = order == "twice, " ? 2 : 1;
          const unsigned int n      = 12 * copies;
          const std::string  what =
            "  " + order +
            (couplings == JoinCouplings::kept ? "join couplings kept" :
                                                "join couplings dropped");
          std::vector<types::global_dof_index> dofs;
          for (unsigned int k = 0; k < serial_cell.size(); ++k)
            for (unsigned int copy = 0; copy < copies; ++copy)
              for (unsigned int q = 0; q < 12; ++q)
                // Vertex by vertex, or component by component.
                dofs.push_back(
                  cell_dofs[12 * k +
                            (order == "components first, " ||
                                 (order == "components first on rank 0, " &&
                                  first_rank) ?
                               3 * (q % 4) + q / 4 :
                               q)]);
          OwnedRowsMatrix rows(layout.locally_owned_dofs,
                               layout.locally_relevant_dofs,
                               relevant_is_join,
                               couplings,
                               MPI_COMM_WORLD);
          rows.set_cells(dofs, n);
          check_equal(what + ", places found point by point",
                      rows.by_point_blocks(),
                      order.empty());
          // Twice: the second assembly starts from zero.
          for (unsigned int assembly = 0; assembly < 2; ++assembly)
            {
              rows.zero();
              for (unsigned int k = 0; k < serial_cell.size(); ++k)
                for (unsigned int i = 0; i < n; ++i)
                  if (rows.row(k, i) >= 0)
                    rows.add_row(k, i, [&](const unsigned int q) {
                      return entry(serial_cell[k],
                                   layout.serial_dof(dofs[n * k + i]),
                                   layout.serial_dof(dofs[n * k + q]));
                    });
            }
          const double scale     = copies * copies;
          const auto   assembled = compare(
            layout, rows, sparsity, serial, couplings, scale, false, {});
          check_equal(what + ", rows of all ranks", assembled.rows, serial.m());
          check_equal(what + ", rows whose columns differ from serial",
                      assembled.wrong_row_lengths,
                      0);
          check_below(what + ", largest entry difference",
                      assembled.largest_difference,
                      0.);
          const auto diagonal   = rows.eliminate_join_dofs();
          const auto eliminated = compare(
            layout, rows, sparsity, serial, couplings, scale, true, diagonal);
          check_equal(what +
                        ", join DoFs eliminated, rows whose columns differ",
                      eliminated.wrong_row_lengths,
                      0);
          check_below(what + ", join DoFs eliminated, largest difference",
                      eliminated.largest_difference,
                      0.);
        }
  }
} // namespace

SOFTFACE_TEST(owned_rows_matrix)
{
  deallog << "ranks: " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
          << std::endl;
  Scene cube;
  make_cube_scene(cube, 8000);
  check("cube", cube);

  ParameterHandler prm;
  Scene            gmsh;
  read_scene("peer_calculix_cube30k.prm", prm, gmsh);
  check("gmsh cube30k", gmsh);
}

// A Trilinos matrix of an MPI rank's own rows, filled by the cells at them
// See fe/owned_rows_matrix.h.

#include <deal.II/lac/exceptions.h>
#include <deal.II/lac/trilinos_index_access.h>

#include <softface/core/release.h>
#include <softface/fe/owned_rows_matrix.h>

#include <Epetra_CrsGraph.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_Map.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace softface
{
  namespace
  {
    // The matrix of a graph whose rows are all inserted (collective).
    void
    make_matrix(Epetra_CrsGraph                &graph,
                const Epetra_Map               &row_map,
                TrilinosWrappers::SparseMatrix &matrix)
    {
      int error = graph.FillComplete(row_map, row_map);
      AssertThrow(error == 0, LACExceptions::ExcTrilinosError(error));
      // One block of indices (and so of values): Epetra's product kernel
      // for optimised storage.
      error = graph.OptimizeStorage();
      AssertThrow(error == 0, LACExceptions::ExcTrilinosError(error));
      // deal.II makes its matrix from an Epetra matrix's graph and maps. A
      // View matrix on the graph holds no values; a Copy one allocated and
      // zeroed as many as the matrix has, only to free them (180 MB and
      // 44 thousand page faults per rank at 2M tetrahedra). So its values
      // must not be copied (copy_values stays false).
      const Epetra_CrsMatrix shape(View, graph);
      matrix.reinit(shape, /*copy_values=*/false);
    }
  } // namespace

  OwnedRowsMatrix::OwnedRowsMatrix(const IndexSet          &owned,
                                   const IndexSet          &relevant,
                                   const std::vector<char> &relevant_is_join,
                                   const JoinCouplings      join_couplings,
                                   const MPI_Comm           communicator)
      : communicator(communicator)
      , owned(owned)
      , relevant(relevant)
      , relevant_is_join(relevant_is_join)
      , join_couplings(join_couplings)
  {
    AssertThrow(relevant_is_join.size() == relevant.n_elements(),
                ExcInternalError());
    // A row is read as a relevant DoF (its join flag, its column).
    AssertThrow((owned & relevant).n_elements() == owned.n_elements(),
                ExcMessage("The owned DoFs must be locally relevant."));
  }

  void
  OwnedRowsMatrix::check_on_every_rank(const bool ok) const
  {
    // An internal error on one rank ends every rank: a rank left alone in
    // the graph's collective FillComplete would wait forever.
    AssertThrow(Utilities::MPI::min(ok ? 1 : 0, communicator) == 1,
                ExcInternalError());
  }

  void
  OwnedRowsMatrix::set_cells(
    const std::vector<types::global_dof_index> &cell_dofs,
    const unsigned int                          n)
  {
    AssertThrow(n > 0 && n <= 255, ExcNotImplemented());
    dofs_per_cell = n;

    // What both ways need: each relevant DoF's global index, and each owned
    // row's place among the relevant DoFs and whether it is a join DoF.
    std::vector<GlobalIndex> relevant_global(relevant.n_elements());
    {
      unsigned int k = 0;
      for (const auto dof : relevant)
        relevant_global[k++] = dof;
    }
    std::vector<unsigned int> row_relevant(owned.n_elements());
    row_is_join.resize(owned.n_elements());
    {
      unsigned int r = 0;
      for (const auto dof : owned)
        {
          row_relevant[r] = relevant.index_within_set(dof);
          row_is_join[r]  = relevant_is_join[row_relevant[r]];
          ++r;
        }
    }

    point_blocks =
      n == 12 &&
      set_point_block_cells(cell_dofs, relevant_global, row_relevant);
    if (point_blocks)
      return;
    std::vector<unsigned int> cells_of_row_start, cells_of_row;
    find_cell_rows(cell_dofs, cells_of_row_start, cells_of_row);
    make_graph_of_cells(relevant_global,
                        row_relevant,
                        cells_of_row_start,
                        cells_of_row);
    sort_cell_columns(relevant_global, row_relevant);

    // Small cells: the places found once.
    cell_entry.clear();
    if (n <= max_dofs_with_positions)
      {
        const Epetra_CrsMatrix &matrix  = trilinos_matrix.trilinos_matrix();
        const std::size_t       n_cells = cell_row.size() / n;
        for (int r = 0; r < matrix.NumMyRows(); ++r)
          AssertThrow(matrix.NumMyEntries(r) < no_entry, ExcNotImplemented());
        cell_entry.assign(n * cell_row.size(), no_entry);
        for (std::size_t c = 0; c < n_cells; ++c)
          for (unsigned int i = 0; i < n; ++i)
            if (cell_row[n * c + i] >= 0)
              walk_row(c, i, [&](const int k, const unsigned int q) {
                cell_entry[n * (n * c + i) + q] = k;
              });
        release(cell_column);
        release(cell_order);
      }
  }

  void
  OwnedRowsMatrix::find_cell_rows(
    const std::vector<types::global_dof_index> &cell_dofs,
    std::vector<unsigned int>                  &cells_of_row_start,
    std::vector<unsigned int>                  &cells_of_row)
  {
    const unsigned int n             = dofs_per_cell;
    const unsigned int n_rows        = owned.n_elements();
    const std::size_t  n_cell_values = cell_dofs.size();
    bool               ok            = true;
    cell_row.assign(n_cell_values, -1);
    cell_column.resize(n_cell_values);
    cells_of_row_start.assign(n_rows + 1, 0);
    for (std::size_t k = 0; k < n_cell_values; ++k)
      {
        const auto dof = cell_dofs[k];
        ok             = ok && relevant.is_element(dof);
        if (!ok)
          break;
        if (owned.is_element(dof))
          {
            cell_row[k] = owned.index_within_set(dof);
            ++cells_of_row_start[cell_row[k] + 1];
          }
        cell_column[k] = relevant.index_within_set(dof);
      }
    check_on_every_rank(ok);
    for (unsigned int r = 0; r < n_rows; ++r)
      cells_of_row_start[r + 1] += cells_of_row_start[r];
    cells_of_row.resize(cells_of_row_start[n_rows]);
    auto next = cells_of_row_start;
    for (std::size_t k = 0; k < n_cell_values; ++k)
      if (cell_row[k] >= 0)
        cells_of_row[next[cell_row[k]]++] = k / n;
  }

  void
  OwnedRowsMatrix::make_graph_of_cells(
    const std::vector<GlobalIndex>  &relevant_global,
    const std::vector<unsigned int> &row_relevant,
    std::vector<unsigned int>       &cells_of_row_start,
    std::vector<unsigned int>       &cells_of_row)
  {
    const unsigned int n      = dofs_per_cell;
    const unsigned int n_rows = owned.n_elements();
    // A row's columns are the DoFs of its cells, once each (a mark per
    // relevant DoF); found twice: their number sizes the graph's rows, then
    // they enter it, row by row.
    const bool                drop = join_couplings == JoinCouplings::dropped;
    std::vector<unsigned int> mark(relevant.n_elements());
    std::vector<GlobalIndex>  columns;
    const auto                find_columns = [&](const unsigned int r) {
      columns.clear();
      if (drop && row_is_join[r])
        {
          columns.push_back(relevant_global[row_relevant[r]]);
          return;
        }
      for (unsigned int c = cells_of_row_start[r];
           c < cells_of_row_start[r + 1];
           ++c)
        for (std::size_t k = std::size_t(n) * cells_of_row[c];
             k < std::size_t(n) * (cells_of_row[c] + 1);
             ++k)
          if (mark[cell_column[k]] != r &&
              !(drop && relevant_is_join[cell_column[k]]))
            {
              mark[cell_column[k]] = r;
              columns.push_back(relevant_global[cell_column[k]]);
            }
    };
    std::vector<int> row_length(n_rows);
    std::fill(mark.begin(), mark.end(), numbers::invalid_unsigned_int);
    for (unsigned int r = 0; r < n_rows; ++r)
      {
        find_columns(r);
        row_length[r] = columns.size();
      }
    const Epetra_Map row_map = owned.make_trilinos_map(communicator, false);
    Epetra_CrsGraph  graph(Copy, row_map, row_length.data(), true);
    std::fill(mark.begin(), mark.end(), numbers::invalid_unsigned_int);
    bool ok = true;
    for (unsigned int r = 0; r < n_rows && ok; ++r)
      {
        find_columns(r);
        ok = graph.InsertGlobalIndices(relevant_global[row_relevant[r]],
                                       columns.size(),
                                       columns.data()) == 0;
      }
    check_on_every_rank(ok);
    release(cells_of_row);
    release(cells_of_row_start);
    release(mark);
    release(row_length);
    make_matrix(graph, row_map, trilinos_matrix);
    zero();
  }

  void
  OwnedRowsMatrix::sort_cell_columns(
    const std::vector<GlobalIndex>  &relevant_global,
    const std::vector<unsigned int> &row_relevant)
  {
    const unsigned int      n          = dofs_per_cell;
    const unsigned int      n_rows     = owned.n_elements();
    const unsigned int      n_relevant = relevant.n_elements();
    const std::size_t       n_cells    = cell_row.size() / n;
    const bool              drop   = join_couplings == JoinCouplings::dropped;
    const Epetra_CrsMatrix &matrix = trilinos_matrix.trilinos_matrix();
    diagonal_column.resize(n_rows);
    for (unsigned int r = 0; r < n_rows; ++r)
      diagonal_column[r] = matrix.LCID(relevant_global[row_relevant[r]]);
    column_is_join.resize(matrix.NumMyCols());
    for (int c = 0; c < matrix.NumMyCols(); ++c)
      column_is_join[c] = relevant_is_join[relevant.index_within_set(
        TrilinosWrappers::global_column_index(matrix, c))];

    // Each cell's columns in the matrix's numbers, sorted, with the cell's
    // DoF of each: with its rows, 9 bytes per cell DoF where a position per
    // entry took 2 bytes per entry (a quadratic cell has 900).
    std::vector<int> matrix_column(n_relevant);
    for (unsigned int k = 0; k < n_relevant; ++k)
      matrix_column[k] = matrix.LCID(relevant_global[k]);
    cell_order.resize(cell_row.size());
    std::vector<std::pair<int, std::uint8_t>> sorted(n);
    bool                                      ok = true;
    for (std::size_t c = 0; c < n_cells; ++c)
      {
        for (unsigned int q = 0; q < n; ++q)
          {
            const unsigned int k = cell_column[n * c + q];
            // A cell's DoF is a column of each of its owned rows (a cell at
            // no owned DoF was given by mistake); with the join couplings
            // dropped, a DoF of cells at owned join DoFs only is none.
            ok        = ok && (matrix_column[k] >= 0 || drop);
            sorted[q] = {matrix_column[k], q};
          }
        std::sort(sorted.begin(), sorted.end());
        for (unsigned int s = 0; s < n; ++s)
          {
            cell_column[n * c + s] = sorted[s].first;
            cell_order[n * c + s]  = sorted[s].second;
          }
      }
    check_on_every_rank(ok);
  }

  bool
  OwnedRowsMatrix::set_point_block_cells(
    const std::vector<types::global_dof_index> &cell_dofs,
    const std::vector<GlobalIndex>             &relevant_global,
    const std::vector<unsigned int>            &row_relevant)
  {
    PointBlockCells cells;
    if (!find_point_blocks(cell_dofs, cells))
      return false;

    const unsigned int        n_rows = owned.n_elements();
    std::vector<int>          row_length, column_of;
    std::vector<unsigned int> block_order;
    std::vector<GlobalIndex>  column_global;
    {
      std::vector<char> is_column;
      count_point_block_rows(cells, row_relevant, row_length, is_column);
      order_point_block_columns(
        relevant_global, is_column, column_of, block_order, column_global);
    }
    const Epetra_Map row_map = owned.make_trilinos_map(communicator, false);
    const Epetra_Map column_map(
      -1, column_global.size(), column_global.data(), 0, row_map.Comm());
    release(column_global);
    Epetra_CrsGraph graph(Copy, row_map, column_map, row_length.data(), true);
    insert_point_block_rows(cells, row_relevant, column_of, block_order, graph);
    release(cells.cells_of_block);
    release(cells.cells_of_block_start);
    release(cells.cell_block);
    make_matrix(graph, row_map, trilinos_matrix);
    zero();
    for (unsigned int r = 0; r < n_rows; ++r)
      AssertThrow(trilinos_matrix.trilinos_matrix().NumMyEntries(r) ==
                      row_length[r] &&
                    row_length[r] < no_entry,
                  ExcInternalError());

    diagonal_column.resize(n_rows);
    for (unsigned int r = 0; r < n_rows; ++r)
      diagonal_column[r] = column_of[row_relevant[r]];
    column_is_join.assign(column_map.NumMyElements(), 0);
    for (unsigned int k = 0; k < relevant.n_elements(); ++k)
      if (column_of[k] >= 0)
        column_is_join[column_of[k]] = relevant_is_join[k];
    release(cell_column);
    release(cell_order);
    return true;
  }

  bool
  OwnedRowsMatrix::find_point_blocks(
    const std::vector<types::global_dof_index> &cell_dofs,
    PointBlockCells                            &cells)
  {
    constexpr unsigned int invalid  = numbers::invalid_unsigned_int;
    const auto             no_index = numbers::invalid_dof_index;
    const std::size_t      n_cells  = cell_dofs.size() / 12;

    // Each cell's points as point blocks among the relevant DoFs (k: DoFs
    // 3k, 3k+1, 3k+2 of relevant) and among the owned rows (or invalid).
    // Any cell that is not such, or has no owned point (given by mistake:
    // the general way refuses it), sends every rank the general way.
    std::vector<unsigned int> &cell_block = cells.cell_block;
    cell_block.resize(4 * n_cells);
    std::vector<unsigned int> cell_row_block(4 * n_cells);
    bool                      blocks = relevant.n_elements() % 3 == 0 &&
                  owned.n_elements() % 3 == 0 &&
                  relevant.n_elements() / 3 < invalid;
    for (std::size_t v = 0; v < 4 * n_cells && blocks; ++v)
      {
        const types::global_dof_index *dofs = &cell_dofs[3 * v];
        const auto                     k = relevant.index_within_set(dofs[0]);
        const auto                     o = owned.index_within_set(dofs[0]);
        blocks = dofs[0] % 3 == 0 && dofs[1] == dofs[0] + 1 &&
                 dofs[2] == dofs[0] + 2 && k != no_index && k % 3 == 0 &&
                 relevant.index_within_set(dofs[2]) == k + 2 &&
                 (o == no_index ?
                    !owned.is_element(dofs[2]) :
                    o % 3 == 0 && owned.index_within_set(dofs[2]) == o + 2);
        cell_block[v]     = k / 3;
        cell_row_block[v] = o == no_index ? invalid : o / 3;
        if (v % 4 == 3)
          blocks = blocks && (cell_row_block[v] != invalid ||
                              cell_row_block[v - 1] != invalid ||
                              cell_row_block[v - 2] != invalid ||
                              cell_row_block[v - 3] != invalid);
      }
    if (Utilities::MPI::min(blocks ? 1 : 0, communicator) == 0)
      return false;

    // The owned rows of each cell, and the cells at each owned point.
    const unsigned int n_row_blocks = owned.n_elements() / 3;
    cell_row.assign(12 * n_cells, -1);
    std::vector<unsigned int> &start = cells.cells_of_block_start;
    start.assign(n_row_blocks + 1, 0);
    for (std::size_t v = 0; v < 4 * n_cells; ++v)
      if (cell_row_block[v] != invalid)
        {
          ++start[cell_row_block[v] + 1];
          for (unsigned int i = 0; i < 3; ++i)
            cell_row[3 * v + i] = 3 * cell_row_block[v] + i;
        }
    for (unsigned int b = 0; b < n_row_blocks; ++b)
      start[b + 1] += start[b];
    cells.cells_of_block.resize(start.back());
    auto next = start;
    for (std::size_t v = 0; v < 4 * n_cells; ++v)
      if (cell_row_block[v] != invalid)
        cells.cells_of_block[next[cell_row_block[v]]++] = v;
    return true;
  }

  void
  OwnedRowsMatrix::find_neighbours(const PointBlockCells     &cells,
                                   const unsigned int         b,
                                   std::vector<unsigned int> &mark,
                                   std::vector<unsigned int> &neighbours)
  {
    neighbours.clear();
    for (unsigned int c = cells.cells_of_block_start[b];
         c < cells.cells_of_block_start[b + 1];
         ++c)
      for (unsigned int a = 0; a < 4; ++a)
        {
          const unsigned int k =
            cells.cell_block[cells.cells_of_block[c] / 4 * 4 + a];
          if (mark[k] != b)
            {
              mark[k] = b;
              neighbours.push_back(k);
            }
        }
  }

  void
  OwnedRowsMatrix::count_point_block_rows(
    const PointBlockCells           &cells,
    const std::vector<unsigned int> &row_relevant,
    std::vector<int>                &row_length,
    std::vector<char>               &is_column) const
  {
    const unsigned int        n_rows   = owned.n_elements();
    const unsigned int        n_blocks = relevant.n_elements() / 3;
    std::vector<unsigned int> mark(n_blocks, numbers::invalid_unsigned_int);
    std::vector<unsigned int> neighbours;
    is_column.assign(3 * n_blocks, 0);
    row_length.assign(n_rows, 0);
    for (unsigned int b = 0; b < n_rows / 3; ++b)
      {
        find_neighbours(cells, b, mark, neighbours);
        unsigned int free_length = 0;
        for (const unsigned int k : neighbours)
          for (unsigned int j = 0; j < 3; ++j)
            if (!dropped_column(3 * k + j))
              {
                ++free_length;
                // A column of the point's rows that keep columns.
                for (unsigned int i = 0; i < 3; ++i)
                  if (!dropped_row(3 * b + i))
                    is_column[3 * k + j] = 1;
              }
        for (unsigned int i = 0; i < 3; ++i)
          {
            const unsigned int r = 3 * b + i;
            row_length[r]        = dropped_row(r) ? 1 : free_length;
            if (dropped_row(r))
              is_column[row_relevant[r]] = 1;
          }
      }
  }

  void
  OwnedRowsMatrix::order_point_block_columns(
    const std::vector<GlobalIndex> &relevant_global,
    std::vector<char>              &is_column,
    std::vector<int>               &column_of,
    std::vector<unsigned int>      &block_order,
    std::vector<GlobalIndex>       &column_global) const
  {
    // The owned DoFs that are columns in their order, then the others
    // ascending (as Epetra makes it from global indices on two ranks). A
    // point's columns stay in the order of their components.
    column_of.assign(relevant.n_elements(), -1);
    block_order.assign(relevant.n_elements() / 3,
                       numbers::invalid_unsigned_int);
    column_global.clear();
    for (const bool own : {true, false})
      for (unsigned int k = 0; k < relevant.n_elements(); ++k)
        if (is_column[k] && owned.is_element(relevant_global[k]) == own)
          {
            column_of[k] = column_global.size();
            if (block_order[k / 3] == numbers::invalid_unsigned_int)
              block_order[k / 3] = column_global.size();
            column_global.push_back(relevant_global[k]);
          }
    release(is_column);
  }

  void
  OwnedRowsMatrix::insert_point_block_rows(
    const PointBlockCells           &cells,
    const std::vector<unsigned int> &row_relevant,
    const std::vector<int>          &column_of,
    const std::vector<unsigned int> &block_order,
    Epetra_CrsGraph                 &graph)
  {
    // Each point's neighbours in column order, its rows' columns, and the
    // place of each of its cells' entries in its rows.
    const unsigned int n_blocks = relevant.n_elements() / 3;
    const std::size_t  n_cells  = cells.cell_block.size() / 4;
    cell_entry.assign(144 * n_cells, no_entry);
    std::vector<unsigned int>  mark(n_blocks, numbers::invalid_unsigned_int);
    std::vector<unsigned int>  neighbours;
    std::vector<int>           columns;
    std::vector<std::uint16_t> place(3 * n_blocks, no_entry);
    bool                       ok = true;
    for (unsigned int b = 0; b < owned.n_elements() / 3 && ok; ++b)
      {
        find_neighbours(cells, b, mark, neighbours);
        std::sort(neighbours.begin(),
                  neighbours.end(),
                  [&](const unsigned int x, const unsigned int y) {
                    return block_order[x] < block_order[y];
                  });
        columns.clear();
        for (const unsigned int k : neighbours)
          for (unsigned int j = 0; j < 3; ++j)
            if (!dropped_column(3 * k + j))
              {
                place[3 * k + j] = columns.size();
                columns.push_back(column_of[3 * k + j]);
              }
            else
              place[3 * k + j] = no_entry;
        for (unsigned int i = 0; i < 3 && ok; ++i)
          {
            const unsigned int r = 3 * b + i;
            if (dropped_row(r))
              {
                int diagonal = column_of[row_relevant[r]];
                ok           = graph.InsertMyIndices(r, 1, &diagonal) == 0;
              }
            else
              ok =
                graph.InsertMyIndices(r, columns.size(), columns.data()) == 0;
          }
        for (unsigned int c = cells.cells_of_block_start[b];
             c < cells.cells_of_block_start[b + 1];
             ++c)
          {
            const std::size_t  cell = cells.cells_of_block[c] / 4;
            const unsigned int a    = cells.cells_of_block[c] % 4;
            for (unsigned int i = 0; i < 3; ++i)
              {
                std::uint16_t *entry =
                  &cell_entry[12 * (12 * cell + 3 * a + i)];
                if (dropped_row(3 * b + i))
                  // Its diagonal alone, the first and only place.
                  entry[3 * a + i] = 0;
                else
                  for (unsigned int q = 0; q < 12; ++q)
                    entry[q] =
                      place[3 * cells.cell_block[4 * cell + q / 3] + q % 3];
              }
          }
      }
    AssertThrow(Utilities::MPI::min(ok ? 1 : 0, communicator) == 1,
                ExcInternalError());
  }

  void
  OwnedRowsMatrix::zero()
  {
    trilinos_matrix = 0.;
    auto &matrix =
      const_cast<Epetra_CrsMatrix &>(trilinos_matrix.trilinos_matrix());
    row_values.resize(matrix.NumMyRows());
    row_columns.resize(matrix.NumMyRows());
    for (int r = 0; r < matrix.NumMyRows(); ++r)
      {
        int n_entries;
        matrix.ExtractMyRowView(r, n_entries, row_values[r], row_columns[r]);
      }
  }

  void
  OwnedRowsMatrix::release_cells()
  {
    release(cell_row);
    release(cell_column);
    release(cell_order);
    release(cell_entry);
  }

  std::vector<double>
  OwnedRowsMatrix::eliminate_join_dofs()
  {
    auto &matrix =
      const_cast<Epetra_CrsMatrix &>(trilinos_matrix.trilinos_matrix());
    std::vector<double> diagonal(row_is_join.size(), 0.);
    for (int r = 0; r < matrix.NumMyRows(); ++r)
      {
        int     n_entries;
        double *values;
        int    *columns;
        matrix.ExtractMyRowView(r, n_entries, values, columns);
        if (!row_is_join[r])
          {
            for (int k = 0; k < n_entries; ++k)
              if (column_is_join[columns[k]])
                values[k] = 0.;
            continue;
          }
        for (int k = 0; k < n_entries; ++k)
          if (columns[k] == diagonal_column[r])
            {
              values[k]   = values[k] != 0. ? std::abs(values[k]) : 1.;
              diagonal[r] = values[k];
            }
          else
            values[k] = 0.;
      }
    return diagonal;
  }
} // namespace softface

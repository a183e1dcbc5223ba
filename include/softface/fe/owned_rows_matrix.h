#ifndef softface_fe_owned_rows_matrix_h
#define softface_fe_owned_rows_matrix_h

#include <deal.II/base/index_set.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <cstdint>
#include <vector>

class Epetra_CrsGraph;

namespace softface
{
  using namespace dealii;

  /**
   * A Trilinos matrix of the rows this MPI rank owns, filled by the cells at
   * them: the linear FEM model's stiffness and the nonlinear
   * models' tangent on several ranks. Every cell at an owned DoF is given to
   * the rank, its own cells and ghost cells alike, so a rank adds to its own
   * rows only and no entry crosses the ranks; a cell at two ranks' DoFs is
   * evaluated on both.
   *
   * The sparsity is made once from the cells (set_cells()), with each row's
   * length known before the graph is built; a cell's entries then go
   * straight into its rows' values (add_row()): a linear tetrahedron's
   * at places found once, a larger cell's by one walk along each row (its
   * places would take more memory than the matrix's share of them).
   * Trilinos' own entry by entry insertion and summation (a look-up of
   * every global index) took as long on each of two ranks as the serial
   * model's whole assembly.
   */
  class OwnedRowsMatrix
  {
  public:
    /// Whether the join DoFs' couplings get a place in the matrix.
    enum class JoinCouplings
    {
      /// All of them: a Newton tangent is multiplied by the join increment
      /// before they are eliminated.
      kept,
      /// None but the join rows' diagonal: a cell's entries elsewhere in a
      /// join row or column are not added (the linear FEM model's
      /// stiffness, whose right-hand side comes from the cells).
      dropped
    };

    /**
     * The rows @p owned; @p relevant are the DoFs of the cells to come, and
     * @p relevant_is_join says which of them (by their place in @p relevant)
     * are join DoFs (eliminate_join_dofs()).
     */
    OwnedRowsMatrix(const IndexSet          &owned,
                    const IndexSet          &relevant,
                    const std::vector<char> &relevant_is_join,
                    const JoinCouplings      join_couplings,
                    const MPI_Comm           communicator);

    /**
     * The cells, by their DoFs (@p dofs_per_cell each, at most 255, one
     * after the other): every cell at a DoF of this rank's. Makes the
     * sparsity and zeroes the matrix. Collective.
     */
    void
    set_cells(const std::vector<types::global_dof_index> &cell_dofs,
              const unsigned int                          dofs_per_cell);

    /// This rank's row (its place among the owned DoFs) of cell @p cell's
    /// DoF @p i; -1 if another rank owns the DoF.
    int
    row(const unsigned int cell, const unsigned int i) const
    {
      Assert(!cell_row.empty(), ExcMessage("No cells: set_cells() first."));
      return cell_row[std::size_t(dofs_per_cell) * cell + i];
    }

    /// Did set_cells() find the places point by point (its cells are
    /// linear tetrahedra whose DoFs are point blocks)?
    bool
    by_point_blocks() const
    {
      return point_blocks;
    }

    /// Zero the matrix (before an assembly). Collective.
    void
    zero();

    /**
     * Add entry(q) to the row of cell @p cell's DoF @p i (an owned one) at
     * the column of the cell's DoF q, for every q.
     */
    template <typename Entry>
    void
    add_row(const unsigned int cell, const unsigned int i, const Entry &entry)
    {
      Assert(!cell_row.empty(), ExcMessage("No cells: set_cells() first."));
      const std::size_t first = std::size_t(dofs_per_cell) * cell;
      const int         r     = cell_row[first + i];
      Assert(r >= 0, ExcMessage("A row of another rank's."));
      double *values = row_values[r];
      if (cell_entry.empty())
        {
          walk_row(cell, i, [&](const int k, const unsigned int q) {
            values[k] += entry(q);
          });
          return;
        }
      const std::uint16_t *position =
        &cell_entry[std::size_t(dofs_per_cell) * (first + i)];
      if (join_couplings == JoinCouplings::kept)
        for (unsigned int q = 0; q < dofs_per_cell; ++q)
          values[position[q]] += entry(q);
      else
        for (unsigned int q = 0; q < dofs_per_cell; ++q)
          if (position[q] != no_entry)
            values[position[q]] += entry(q);
    }

    /**
     * Eliminate the join DoFs in place, as
     * ConstrainedSystem::eliminate_join_dofs() does on a serial matrix: a
     * join row keeps only its diagonal, as its magnitude (1 if it is 0), and
     * a free row loses its join columns. Returns each row's diagonal as
     * kept (by this rank's rows; free rows' are 0).
     */
    std::vector<double>
    eliminate_join_dofs();

    /// Forget the cells (set_cells()) once the matrix is assembled for good
    /// (a linear model's): their rows and places take more memory than the
    /// matrix at linear tetrahedra (336 bytes a cell), and ML's setup comes
    /// after. add_row() and row() then need set_cells() again.
    void
    release_cells();

    const TrilinosWrappers::SparseMatrix &
    matrix() const
    {
      return trilinos_matrix;
    }

    /// The matrix, for a product or a copy (its sparsity must not change).
    TrilinosWrappers::SparseMatrix &
    matrix()
    {
      return trilinos_matrix;
    }

  private:
    using GlobalIndex = TrilinosWrappers::types::int_type;

    /// Throw on every rank if @p ok is false on one (a rank left alone in
    /// a collective call would wait forever).
    void
    check_on_every_rank(const bool ok) const;

    /// The general way, step 1: each cell's DoFs as this rank's rows
    /// (cell_row) and as locally relevant DoFs (cell_column); the cells at
    /// each owned row (those of row r from cells_of_row_start[r]).
    void
    find_cell_rows(const std::vector<types::global_dof_index> &cell_dofs,
                   std::vector<unsigned int> &cells_of_row_start,
                   std::vector<unsigned int> &cells_of_row);

    /// Step 2: the graph whose row's columns are the DoFs of its cells,
    /// and the matrix on it (the cells at each row released).
    void
    make_graph_of_cells(const std::vector<GlobalIndex>  &relevant_global,
                        const std::vector<unsigned int> &row_relevant,
                        std::vector<unsigned int>       &cells_of_row_start,
                        std::vector<unsigned int>       &cells_of_row);

    /// Step 3: the diagonal's column of each row, which columns are join
    /// DoFs, and each cell's columns in the matrix's numbers, sorted, with
    /// the cell's DoF of each (cell_order).
    void
    sort_cell_columns(const std::vector<GlobalIndex>  &relevant_global,
                      const std::vector<unsigned int> &row_relevant);

    /// Linear tetrahedra whose DoFs are point blocks (set_point_block_cells()).
    struct PointBlockCells
    {
      /// Per cell and vertex: its point among the relevant DoFs' blocks.
      std::vector<unsigned int> cell_block;
      /// The cells at owned point b, as 4 cell + vertex, are
      /// cells_of_block[cells_of_block_start[b] ...].
      std::vector<unsigned int>  cells_of_block_start;
      std::vector<std::uint64_t> cells_of_block;
    };

    /**
     * set_cells() where every cell is a linear tetrahedron whose DoFs come
     * vertex by vertex as point blocks (3p, 3p+1, 3p+2), as a P1 layout's
     * do: the three rows of a point share their columns, so a row's columns
     * and the places of the cells' entries are found once per point from its
     * cells' points (as PointBlockPattern does on one rank), and the graph
     * is given its column map in local numbers. Taken when every rank's
     * cells are such (false otherwise, with nothing changed). Collective.
     * @p relevant_global holds each relevant DoF's global index,
     * @p row_relevant each owned row's place among the relevant DoFs.
     */
    bool
    set_point_block_cells(const std::vector<types::global_dof_index> &cell_dofs,
                          const std::vector<GlobalIndex>  &relevant_global,
                          const std::vector<unsigned int> &row_relevant);

    /// Whether every rank's cells are point blocks with an owned point
    /// each (collective); if so, @p cells and cell_row.
    bool
    find_point_blocks(const std::vector<types::global_dof_index> &cell_dofs,
                      PointBlockCells                            &cells);

    /// The points of owned point @p b's cells, once each (b among them),
    /// in @p neighbours; @p mark: a point's last b (invalid at first).
    static void
    find_neighbours(const PointBlockCells     &cells,
                    const unsigned int         b,
                    std::vector<unsigned int> &mark,
                    std::vector<unsigned int> &neighbours);

    /// Each owned row's length, and which relevant DoFs are columns.
    void
    count_point_block_rows(const PointBlockCells           &cells,
                           const std::vector<unsigned int> &row_relevant,
                           std::vector<int>                &row_length,
                           std::vector<char>               &is_column) const;

    /// The column map (@p column_global): the owned DoFs that are columns,
    /// then the others; each relevant DoF's column (-1: none) and each
    /// point's first column. Releases @p is_column.
    void
    order_point_block_columns(const std::vector<GlobalIndex> &relevant_global,
                              std::vector<char>              &is_column,
                              std::vector<int>               &column_of,
                              std::vector<unsigned int>      &block_order,
                              std::vector<GlobalIndex> &column_global) const;

    /// The rows' columns into @p graph, and the place of each cell's
    /// entries in its rows (cell_entry).
    void
    insert_point_block_rows(const PointBlockCells           &cells,
                            const std::vector<unsigned int> &row_relevant,
                            const std::vector<int>          &column_of,
                            const std::vector<unsigned int> &block_order,
                            Epetra_CrsGraph                 &graph);

    /// With the join couplings dropped, a join DoF's row keeps its diagonal
    /// alone and no row keeps a join DoF's column.
    bool
    dropped_row(const unsigned int r) const
    {
      return join_couplings == JoinCouplings::dropped && row_is_join[r];
    }
    bool
    dropped_column(const unsigned int k) const
    {
      return join_couplings == JoinCouplings::dropped &&
             bool(relevant_is_join[k]);
    }

    /**
     * Call at(k, q) for each of cell @p cell's DoFs q that has a place k in
     * the row of its DoF @p i (an owned one). The cell's columns and the
     * row's are both sorted: one walk along the row finds them all.
     */
    template <typename At>
    void
    walk_row(const unsigned int cell, const unsigned int i, const At &at) const
    {
      Assert(!cell_row.empty(), ExcMessage("No cells: set_cells() first."));
      const std::size_t   first        = std::size_t(dofs_per_cell) * cell;
      const int           r            = cell_row[first + i];
      const int          *columns      = row_columns[r];
      const int          *cell_columns = &cell_column[first];
      const std::uint8_t *order        = &cell_order[first];
      int                 k            = 0;
      if (join_couplings == JoinCouplings::kept)
        for (unsigned int s = 0; s < dofs_per_cell; ++s)
          {
            while (columns[k] != cell_columns[s])
              ++k;
            at(k, order[s]);
          }
      else if (row_is_join[r])
        {
          // Its diagonal alone (the cell's DoF i, and any repeat of it).
          for (unsigned int s = 0; s < dofs_per_cell; ++s)
            if (cell_columns[s] == diagonal_column[r])
              at(0, order[s]);
        }
      else
        for (unsigned int s = 0; s < dofs_per_cell; ++s)
          {
            // A join DoF, or a DoF of no owned free row (-1).
            if (cell_columns[s] < 0 || column_is_join[cell_columns[s]])
              continue;
            while (columns[k] != cell_columns[s])
              ++k;
            at(k, order[s]);
          }
    }

    /// Cells of at most this many DoFs keep each entry's place in its row
    /// (2 bytes per entry: 288 for a linear tetrahedron, where a quadratic
    /// one's 900 entries would take 1.8 kB): their assembly adds without
    /// walking the rows, as fast as a serial one.
    static constexpr unsigned int  max_dofs_with_positions = 12;
    static constexpr std::uint16_t no_entry                = 0xffff;

    const MPI_Comm                 communicator;
    const IndexSet                 owned;
    const IndexSet                 relevant;
    std::vector<char>              relevant_is_join;
    const JoinCouplings            join_couplings;
    TrilinosWrappers::SparseMatrix trilinos_matrix;

    /// Per cell and DoF: its row among this rank's rows (-1 if another
    /// rank owns it); per cell, its columns in the matrix's local numbers,
    /// sorted, and the cell's DoF of each (walk_row()).
    unsigned int              dofs_per_cell = 0;
    bool                      point_blocks  = false;
    std::vector<int>          cell_row;
    std::vector<int>          cell_column;
    std::vector<std::uint8_t> cell_order;
    /// For small cells instead: per cell, row i and DoF q, the place in row
    /// i's values (no_entry: none, a dropped join coupling).
    std::vector<std::uint16_t> cell_entry;
    /// The values and columns of each row in the Trilinos matrix (looked up
    /// after each zeroing, which may move them).
    std::vector<double *> row_values;
    std::vector<int *>    row_columns;
    /// By row: whether it is a join DoF and its diagonal's column; by the
    /// matrix's columns: whether they are join DoFs.
    std::vector<char> row_is_join;
    std::vector<int>  diagonal_column;
    std::vector<char> column_is_join;
  };
} // namespace softface

#endif

#ifndef softface_fe_owned_rows_matrix_h
#define softface_fe_owned_rows_matrix_h

#include <deal.II/base/index_set.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <cstdint>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * A Trilinos matrix of the rows this MPI rank owns, filled by the cells at
   * them (issue 20): the linear FEM model's stiffness and the nonlinear
   * models' tangent on several ranks. Every cell at an owned DoF is given to
   * the rank, its own cells and ghost cells alike, so a rank adds to its own
   * rows only and no entry crosses the ranks; a cell at two ranks' DoFs is
   * evaluated on both.
   *
   * The sparsity is made once from the cells (set_cells()), with each row's
   * length known before the graph is built; a cell's entries then go
   * straight into its rows' values (add_row()), found by one walk along
   * each row. Trilinos' own entry by entry insertion and summation (a
   * look-up of every global index) took as long on each of two ranks as
   * the serial model's whole assembly.
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
      return cell_row[std::size_t(dofs_per_cell) * cell + i];
    }

    /// Zero the matrix (before an assembly).
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
      // The cell's columns and the row's are both sorted: one walk along
      // the row finds them all.
      const std::size_t   first        = std::size_t(dofs_per_cell) * cell;
      const int           r            = cell_row[first + i];
      const int          *columns      = row_columns[r];
      double             *values       = row_values[r];
      const int          *cell_columns = &cell_column[first];
      const std::uint8_t *order        = &cell_order[first];
      int                 k            = 0;
      if (join_couplings == JoinCouplings::kept)
        for (unsigned int s = 0; s < dofs_per_cell; ++s)
          {
            while (columns[k] != cell_columns[s])
              ++k;
            values[k] += entry(order[s]);
          }
      else if (row_is_join[r])
        values[0] += entry(i);
      else
        for (unsigned int s = 0; s < dofs_per_cell; ++s)
          {
            // A join DoF, or a DoF of no owned free row (-1).
            if (cell_columns[s] < 0 || column_is_join[cell_columns[s]])
              continue;
            while (columns[k] != cell_columns[s])
              ++k;
            values[k] += entry(order[s]);
          }
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
    const MPI_Comm                 communicator;
    const IndexSet                 owned;
    const IndexSet                 relevant;
    std::vector<char>              relevant_is_join;
    const JoinCouplings            join_couplings;
    TrilinosWrappers::SparseMatrix trilinos_matrix;

    /// Per cell and DoF: its row among this rank's rows (-1 if another
    /// rank owns it); per cell, its columns in the matrix's local numbers,
    /// sorted, and the cell's DoF of each.
    unsigned int              dofs_per_cell = 0;
    std::vector<int>          cell_row;
    std::vector<int>          cell_column;
    std::vector<std::uint8_t> cell_order;
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

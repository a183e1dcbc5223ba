#ifndef softface_fe_row_partition_h
#define softface_fe_row_partition_h

#include <deal.II/base/types.h>

#include <array>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The cells of a P1 mesh split for assembly on several threads (issue
   * 16). The rows (DoFs) are cut into contiguous ranges, one per part; a
   * part visits, in ascending order, every cell with a row in its range and
   * adds only those rows. Each row then sums its cells' entries in the same
   * order on any number of threads: matrices and forces are bitwise the
   * serial ones, with no locks and no colouring. The price is that a cell
   * on a range border is computed by two parts; with DoFs numbered in cell
   * order (Mesh::order_for_locality, or a generated grid) that is a few per
   * cent of the cells.
   */
  class RowPartition
  {
  public:
    /// Split the rows 0..n_rows-1 of the cells with @p cell_dofs into
    /// @p n_parts ranges.
    void
    reinit(
      const std::vector<std::array<types::global_dof_index, 12>> &cell_dofs,
      types::global_dof_index                                     n_rows,
      unsigned int                                                n_parts);

    unsigned int
    n_parts() const
    {
      return part_cells.size();
    }

    /// The cells part @p p visits, ascending.
    const std::vector<unsigned int> &
    cells(const unsigned int p) const
    {
      return part_cells[p];
    }

    /// Whether part @p p adds row @p row.
    bool
    owns(const unsigned int p, const types::global_dof_index row) const
    {
      return row >= first_row[p] && row < first_row[p + 1];
    }

    /// The first row of part @p p; first_row_of(n_parts()) is n_rows.
    types::global_dof_index
    first_row_of(const unsigned int p) const
    {
      return first_row[p];
    }

  private:
    std::vector<types::global_dof_index>   first_row;
    std::vector<std::vector<unsigned int>> part_cells;
  };
} // namespace softface

#endif

// Cells split by the rows they add to, for threaded assembly.

#include <softface/fe/row_partition.h>

#include <algorithm>

namespace softface
{
  void
  RowPartition::reinit(
    const std::vector<std::array<types::global_dof_index, 12>> &cell_dofs,
    const types::global_dof_index                               n_rows,
    const unsigned int                                          n_parts)
  {
    const unsigned int parts =
      std::max(1u, std::min<unsigned int>(n_parts, n_rows / 3 + 1));
    first_row.resize(parts + 1);
    // Whole vertices (three rows) per part.
    for (unsigned int p = 0; p <= parts; ++p)
      first_row[p] = std::min<types::global_dof_index>(
        n_rows,
        3 * ((static_cast<unsigned long long>(n_rows / 3) * p + parts - 1) /
             parts));
    first_row[parts] = n_rows;
    part_cells.assign(parts, {});
    for (auto &cells : part_cells)
      cells.reserve(cell_dofs.size() / parts);
    for (unsigned int c = 0; c < cell_dofs.size(); ++c)
      {
        // A cell's rows fall in a few parts at most: each part once, in
        // part order.
        std::array<unsigned int, 12> parts_of_rows;
        for (unsigned int r = 0; r < 12; ++r)
          parts_of_rows[r] = std::upper_bound(first_row.begin() + 1,
                                              first_row.end(),
                                              cell_dofs[c][r]) -
                             first_row.begin() - 1;
        std::sort(parts_of_rows.begin(), parts_of_rows.end());
        for (unsigned int r = 0; r < 12; ++r)
          if (r == 0 || parts_of_rows[r] != parts_of_rows[r - 1])
            part_cells[parts_of_rows[r]].push_back(c);
      }
  }
} // namespace softface

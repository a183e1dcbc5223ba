// The P1 point-block sparsity and the places of its entries (fe): made from
// the points' neighbours, the same work per cell on any mesh.

#include <softface/fe/point_block_pattern.h>

#include <limits>

namespace softface
{
  PointBlockPattern::PointBlockPattern(const PointMesh &points)
      : points(points)
  {
    // Places are unsigned int, as the nonlinear FEM stores them.
    AssertThrow(n_entries() <= std::numeric_limits<unsigned int>::max(),
                ExcMessage("PointBlockPattern: the matrix has more entries "
                           "than an unsigned int counts."));
  }

  std::size_t
  PointBlockPattern::n_entries() const
  {
    return 9 * (points.neighbour.size() + points.n_points());
  }

  void
  PointBlockPattern::make_sparsity(SparsityPattern &sparsity) const
  {
    const auto               &row_start = points.row_start;
    const auto               &neighbour = points.neighbour;
    const unsigned int        n_points  = points.n_points();
    std::vector<unsigned int> row_lengths(3 * n_points);
    for (unsigned int p = 0; p < n_points; ++p)
      for (unsigned int i = 0; i < 3; ++i)
        row_lengths[3 * p + i] = 3 * (row_start[p + 1] - row_start[p] + 1);
    sparsity.reinit(3 * n_points, 3 * n_points, row_lengths);
    std::vector<SparsityPattern::size_type> columns;
    for (unsigned int p = 0; p < n_points; ++p)
      {
        // Its neighbours and itself, ascending, three columns each.
        columns.clear();
        bool own_block_added = false;
        for (unsigned int k = row_start[p]; k <= row_start[p + 1]; ++k)
          {
            const bool at_end = (k == row_start[p + 1]);
            if (!own_block_added && (at_end || neighbour[k] > p))
              {
                for (unsigned int j = 0; j < 3; ++j)
                  columns.push_back(3 * p + j);
                own_block_added = true;
              }
            if (!at_end)
              for (unsigned int j = 0; j < 3; ++j)
                columns.push_back(3 * neighbour[k] + j);
          }
        for (unsigned int i = 0; i < 3; ++i)
          sparsity.add_entries(3 * p + i, columns.begin(), columns.end(), true);
      }
    sparsity.compress();
  }

  void
  PointBlockPattern::cell_positions(const unsigned int cell,
                                    unsigned int      *positions) const
  {
    const auto &row_start = points.row_start;
    const auto &p         = points.tetrahedra[cell];
    for (unsigned int a = 0; a < 4; ++a)
      {
        // Rows of point p[a]: 3 (its neighbours + 1) entries each, after
        // the 9 (neighbours + 1) of every point before it. A square
        // pattern stores the diagonal first, then the other columns
        // ascending.
        const unsigned int v      = p[a];
        const unsigned int length = 3 * (row_start[v + 1] - row_start[v] + 1);
        const unsigned int first  = 9 * (row_start[v] + v);
        for (unsigned int b = 0; b < 4; ++b)
          {
            const unsigned int w = p[b];
            // Columns of the row before column 3w (the diagonal counted):
            // three per point of the row (its neighbours and v) before w.
            const unsigned int before =
              3 * (points.neighbours_before(v, w) + (v < w));
            for (unsigned int i = 0; i < 3; ++i)
              {
                const unsigned int row         = 3 * v + i;
                const unsigned int row_first   = first + i * length;
                unsigned int      *row_entries = positions + 12 * (3 * a + i);
                for (unsigned int j = 0; j < 3; ++j)
                  {
                    const unsigned int column = 3 * w + j;
                    row_entries[3 * b + j] =
                      (column == row) ?
                        row_first :
                        row_first + 1 + before + j - (row < column);
                  }
              }
          }
      }
  }
} // namespace softface

// Blocks of points coloured for threaded Gauss-Seidel sweeps.

#include <softface/core/threads.h>
#include <softface/models/block_colouring.h>

#include <algorithm>
#include <numeric>

namespace softface
{
  BlockColouring::BlockColouring(const unsigned int               n_points,
                                 const std::vector<unsigned int> &row_start,
                                 const std::vector<unsigned int> &neighbour)
  {
    constexpr unsigned int size     = 256;
    const unsigned int     n_blocks = (n_points + size - 1) / size;
    for (unsigned int b = 0; b <= n_blocks; ++b)
      block_start.push_back(std::min(n_points, b * size));

    // Greedy: each block takes the smallest colour none of its neighbour
    // blocks coloured before it has.
    std::vector<unsigned int> colour_of(n_blocks, 0);
    std::vector<unsigned int> used_by; // the block that last used a colour
    for (unsigned int b = 0; b < n_blocks; ++b)
      {
        for (unsigned int j = block_start[b]; j < block_start[b + 1]; ++j)
          for (unsigned int i = row_start[j]; i < row_start[j + 1]; ++i)
            {
              const unsigned int other = neighbour[i] / size;
              if (other < b)
                used_by[colour_of[other]] = b;
            }
        unsigned int c = 0;
        while (c < used_by.size() && used_by[c] == b)
          ++c;
        if (c == used_by.size())
          used_by.push_back(n_blocks);
        colour_of[b] = c;
        if (colours.size() <= c)
          colours.resize(c + 1);
        colours[c].push_back(b);
      }
  }

  BlockColouring::BlockColouring(const unsigned int n_points)
      : block_start{0, n_points}
      , colours{{0}}
  {}

  void
  BlockColouring::sweep(
    const std::vector<unsigned int>                                   &points,
    const std::function<void(unsigned int, std::size_t, std::size_t)> &update,
    const std::function<void(unsigned int, std::size_t)> &after_colour) const
  {
    // Each block's points, written by its task.
    std::vector<std::size_t> n_updated;
    for (unsigned int c = 0; c < colours.size(); ++c)
      {
        const auto &blocks = colours[c];
        n_updated.assign(blocks.size(), 0);
        Threads::run_tasks(blocks.size(), [&](const unsigned int k) {
          const unsigned int b = blocks[k];
          const auto         begin =
            std::lower_bound(points.begin(), points.end(), block_start[b]);
          const auto end =
            std::lower_bound(begin, points.end(), block_start[b + 1]);
          n_updated[k] = end - begin;
          update(b, begin - points.begin(), end - points.begin());
        });
        if (after_colour)
          after_colour(c,
                       std::accumulate(n_updated.begin(),
                                       n_updated.end(),
                                       std::size_t(0)));
      }
  }
} // namespace softface

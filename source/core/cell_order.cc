// Cells along a Hilbert curve, vertices in first-touch order.

#include <deal.II/base/utilities.h>

#include <softface/core/cell_order.h>
#include <softface/core/threads.h>

#include <algorithm>
#include <array>
#include <cstdint>

namespace softface
{
  namespace Mesh
  {
    namespace
    {
      /**
       * Bit j of @p x (j < 21) moved to bit 3j.
       */
      std::uint64_t
      spread_bits(std::uint64_t x)
      {
        x &= 0x1fffff;
        x = (x | x << 32) & 0x1f00000000ffffULL;
        x = (x | x << 16) & 0x1f0000ff0000ffULL;
        x = (x | x << 8) & 0x100f00f00f00f00fULL;
        x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
        x = (x | x << 2) & 0x1249249249249249ULL;
        return x;
      }

      /**
       * The Hilbert index of integer coordinates @p x of @p bits bits each:
       * Skilling's transform of the axes to the curve's transposed index
       * ("Programming the Hilbert curve", AIP Conf. Proc. 707, 2004), the
       * algorithm of deal.II's inverse_Hilbert_space_filling_curve(), and
       * its bits interleaved into one integer as pack_integers() packs
       * deal.II's answer. Without branches on the bits: deal.II's bit by
       * bit walk mispredicted about every other bit (0.19 s of a 491k-cell
       * gmsh mesh's read).
       */
      std::uint64_t
      hilbert_key(std::array<std::uint64_t, 3> x, const int bits)
      {
        const std::uint64_t top = std::uint64_t(1) << (bits - 1);
        // Inverse undo: per bit from the top, invert the lower bits of x[0]
        // where x[i] has the bit, else exchange them between x[0] and x[i].
        for (std::uint64_t q = top; q > 1; q >>= 1)
          {
            const std::uint64_t low = q - 1;
            for (unsigned int i = 0; i < 3; ++i)
              {
                const std::uint64_t set = std::uint64_t(0) - ((x[i] & q) != 0);
                x[0] ^= low & set;
                const std::uint64_t t = (x[0] ^ x[i]) & low & ~set;
                x[0] ^= t;
                x[i] ^= t;
              }
          }
        // Gray encode.
        x[1] ^= x[0];
        x[2] ^= x[1];
        std::uint64_t t = 0;
        for (std::uint64_t q = top; q > 1; q >>= 1)
          t ^= (q - 1) & (std::uint64_t(0) - ((x[2] & q) != 0));
        for (auto &xi : x)
          xi ^= t;
        return (spread_bits(x[0]) << 2) | (spread_bits(x[1]) << 1) |
               spread_bits(x[2]);
      }
    } // namespace

    std::vector<std::uint64_t>
    hilbert_keys(const std::vector<Point<3>> &points, const int bits)
    {
      // deal.II's inverse_Hilbert_space_filling_curve() maps the points'
      // bounding box to integers, then walks each point's bits (0.28 s for
      // 491k points). The walk is per point: done here in pieces on the
      // threads, after the same mapping (long double, as deal.II's), with
      // the transform of hilbert_key(), so the keys are deal.II's on any
      // number of threads.
      Assert(bits >= 1 && bits <= 21, ExcIndexRange(bits, 1, 22));
      std::vector<std::uint64_t> keys(points.size());
      if (points.empty())
        return keys;
      Point<3> low = points[0], high = points[0];
      for (const Point<3> &p : points)
        for (unsigned int d = 0; d < 3; ++d)
          {
            low[d]  = std::min(low[d], p[d]);
            high[d] = std::max(high[d], p[d]);
          }
      std::array<long double, 3> extent;
      for (unsigned int d = 0; d < 3; ++d)
        extent[d] =
          static_cast<long double>(high[d]) - static_cast<long double>(low[d]);
      if (!(extent[0] > 0 && extent[1] > 0 && extent[2] > 0))
        {
          // A flat set of points: deal.II's own treatment of the flat axes.
          const auto curve =
            Utilities::inverse_Hilbert_space_filling_curve(points, bits);
          for (std::size_t i = 0; i < points.size(); ++i)
            keys[i] = Utilities::pack_integers<3>(curve[i], bits);
          return keys;
        }
      const std::uint64_t largest  = (std::uint64_t(1) << bits) - 1;
      const std::size_t   piece    = 16384;
      const std::size_t   n_pieces = (points.size() + piece - 1) / piece;
      Threads::run_tasks(n_pieces, [&](const unsigned int k) {
        const std::size_t begin = k * piece;
        const std::size_t end   = std::min(points.size(), begin + piece);
        for (std::size_t i = begin; i < end; ++i)
          {
            std::array<std::uint64_t, 3> integers;
            for (unsigned int d = 0; d < 3; ++d)
              {
                const long double v = (static_cast<long double>(points[i][d]) -
                                       static_cast<long double>(low[d])) /
                                      extent[d];
                integers[d] = static_cast<std::uint64_t>(
                  v * static_cast<long double>(largest));
              }
            keys[i] = hilbert_key(integers, bits);
          }
      });
      return keys;
    }

    std::vector<unsigned int>
    order_for_locality(std::vector<Point<3>>    &vertices,
                       std::vector<CellData<3>> &cells,
                       SubCellData              &faces)
    {
      // 21 bits per direction: the packed key fits 64 bits, and 2^21 boxes
      // per edge separate any two cells of a mesh that fits in memory.
      constexpr int         bits = 21;
      std::vector<Point<3>> centres(cells.size());
      for (std::size_t c = 0; c < cells.size(); ++c)
        {
          Point<3> sum;
          for (const unsigned int v : cells[c].vertices)
            sum += vertices[v];
          centres[c] = sum / static_cast<double>(cells[c].vertices.size());
        }
      const std::vector<std::uint64_t> curve = hilbert_keys(centres, bits);

      // Equal keys keep their order (the pairs compare the cell last), so
      // the result does not depend on the sort's internals.
      std::vector<std::pair<std::uint64_t, unsigned int>> key(cells.size());
      for (std::size_t c = 0; c < cells.size(); ++c)
        key[c] = {curve[c], static_cast<unsigned int>(c)};
      std::sort(key.begin(), key.end());
      std::vector<unsigned int> old_cell(cells.size());
      for (std::size_t i = 0; i < cells.size(); ++i)
        old_cell[i] = key[i].second;

      // Vertices numbered as the cells in curve order first touch them;
      // vertices of no cell after the others.
      const unsigned int        unused = numbers::invalid_unsigned_int;
      std::vector<unsigned int> new_vertex(vertices.size(), unused);
      std::vector<Point<3>>     sorted_vertices;
      sorted_vertices.reserve(vertices.size());
      for (const unsigned int c : old_cell)
        for (const unsigned int v : cells[c].vertices)
          if (new_vertex[v] == unused)
            {
              new_vertex[v] = sorted_vertices.size();
              sorted_vertices.push_back(vertices[v]);
            }
      for (std::size_t v = 0; v < vertices.size(); ++v)
        if (new_vertex[v] == unused)
          {
            new_vertex[v] = sorted_vertices.size();
            sorted_vertices.push_back(vertices[v]);
          }
      vertices = std::move(sorted_vertices);
      for (auto &cell : cells)
        for (unsigned int &v : cell.vertices)
          v = new_vertex[v];
      for (auto &face : faces.boundary_quads)
        for (unsigned int &v : face.vertices)
          v = new_vertex[v];
      for (auto &line : faces.boundary_lines)
        for (unsigned int &v : line.vertices)
          v = new_vertex[v];

      // Then the cells in the order of their vertex numbers, as a grid's
      // cells are: a matrix row is assembled from cells that follow each
      // other, and its columns arrive nearly sorted (on a 105k gmsh cube
      // sparsity and assembly are 5-10 % faster than in curve order).
      // (Ties keep the curve order: the pairs compare it last.)
      std::vector<std::pair<std::array<unsigned int, 4>, unsigned int>>
        sorted_vertices_of(cells.size());
      for (std::size_t i = 0; i < cells.size(); ++i)
        {
          const auto &vertices_of_cell   = cells[old_cell[i]].vertices;
          std::array<unsigned int, 4> &s = sorted_vertices_of[i].first;
          s.fill(0);
          for (unsigned int k = 0; k < 4 && k < vertices_of_cell.size(); ++k)
            s[k] = vertices_of_cell[k];
          std::sort(s.begin(), s.end());
          sorted_vertices_of[i].second = i;
        }
      sort_by_first_point(sorted_vertices_of,
                          vertices.size(),
                          [](const auto &item) { return item.first[0]; });
      {
        const std::vector<unsigned int> curve_order = old_cell;
        for (std::size_t i = 0; i < cells.size(); ++i)
          old_cell[i] = curve_order[sorted_vertices_of[i].second];
      }

      std::vector<CellData<3>> sorted_cells;
      sorted_cells.reserve(cells.size());
      for (const unsigned int c : old_cell)
        sorted_cells.push_back(std::move(cells[c]));
      cells = std::move(sorted_cells);
      return old_cell;
    }
  } // namespace Mesh
} // namespace softface

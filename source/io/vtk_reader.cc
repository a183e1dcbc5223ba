// softface's reader of legacy VTK unstructured grids. deal.II's
// GridIn::read_vtk trusts its input (a point index past the end or a cell
// type that does not match its point count overflows the heap);
// this reader checks every word before the mesh is built.

#include <softface/core/error.h>
#include <softface/io/text_tokens.h>
#include <softface/io/vtk_reader.h>

#include <cmath>
#include <limits>

namespace softface
{
  namespace Mesh
  {
    namespace
    {
      constexpr std::int64_t max_index = std::numeric_limits<int>::max();
      constexpr double       max_id =
        std::numeric_limits<types::material_id>::max() - 1.;

      bool
      is_id_name(const std::string &name)
      {
        return name == "MaterialID" || name == "material_id" ||
               name == "gmsh:physical" || name == "CellEntityIds";
      }

      class VtkReader
      {
      public:
        explicit VtkReader(const std::string &filename)
            : in(filename)
        {}

        MeshData
        read()
        {
          data.element_word              = "cell";
          const std::string version_line = in.line_text("the version line");
          const std::string prefix       = "# vtk DataFile Version ";
          if (version_line.rfind(prefix, 0) != 0)
            in.fail("a legacy VTK file starts with '" + prefix +
                    "x.y', this one with '" + version_line.substr(0, 40) + "'");
          const std::string version        = version_line.substr(prefix.size());
          const bool        offsets_layout = version.rfind("5", 0) == 0;
          in.line_text("the title line");
          const std::string encoding = in.line_text("ASCII or BINARY");
          if (encoding == "BINARY")
            in.fail("the file is BINARY; softface reads ASCII legacy VTK "
                    "files (or .vtu in any encoding)");
          if (encoding != "ASCII")
            in.fail("expected ASCII but found '" + encoding.substr(0, 40) +
                    "'");
          in.expect("DATASET");
          const std::string dataset(in.word("the dataset type"));
          if (dataset != "UNSTRUCTURED_GRID")
            in.fail("the dataset is " + dataset.substr(0, 40) +
                    "; softface reads UNSTRUCTURED_GRID");

          while (!in.at_end())
            {
              const std::string keyword(in.word("a section"));
              if (keyword == "POINTS")
                points();
              else if (keyword == "CELLS")
                offsets_layout ? cells_5() : cells_2();
              else if (keyword == "CELL_TYPES")
                cell_types();
              else if (keyword == "CELL_DATA")
                data_section(true);
              else if (keyword == "POINT_DATA")
                data_section(false);
              else if (keyword == "FIELD")
                field(false);
              else if (keyword == "METADATA")
                metadata();
              else
                in.fail("unexpected '" + keyword.substr(0, 40) + "'");
            }
          if (!have_points)
            in.fail("there is no POINTS section");
          if (!have_types)
            in.fail("there is no CELLS or no CELL_TYPES section");
          return build();
        }

      private:
        TextTokens                             in;
        MeshData                               data;
        bool                                   have_points = false;
        bool                                   have_types  = false;
        std::vector<std::vector<unsigned int>> cell_points;
        std::vector<std::size_t>               cell_lines;
        std::vector<std::int64_t>              types;
        std::vector<double>                    ids;

        void
        points()
        {
          if (have_points)
            in.fail("a second POINTS section");
          const std::uint64_t n = in.count("the number of points", 3);
          in.word("the points' data type");
          data.vertices.resize(n);
          for (auto &x : data.vertices)
            for (unsigned int d = 0; d < 3; ++d)
              x[d] = in.coordinate("a point coordinate");
          have_points = true;
        }

        unsigned int
        point_index(const std::size_t cell)
        {
          if (!have_points)
            in.fail("CELLS comes before POINTS");
          const std::int64_t index = in.integer("a point index", 0, max_index);
          if (static_cast<std::uint64_t>(index) >= data.vertices.size())
            in.fail("cell " + std::to_string(cell) + " refers to point " +
                    std::to_string(index) + ", but there are " +
                    std::to_string(data.vertices.size()) + " points");
          return index;
        }

        void
        check_no_cells()
        {
          if (!cell_points.empty())
            in.fail("a second CELLS section");
        }

        // Versions before 5: each cell is its point count and its points.
        void
        cells_2()
        {
          check_no_cells();
          const std::uint64_t n    = in.count("the number of cells", 2);
          const std::uint64_t size = in.count("the size of the cell list", 1);
          std::uint64_t       read = 0;
          cell_points.resize(n);
          cell_lines.resize(n);
          for (std::uint64_t c = 0; c < n; ++c)
            {
              const std::int64_t k = in.integer("a cell's point count", 0, 64);
              cell_lines[c]        = in.line();
              read += 1 + k;
              if (read > size)
                in.fail("the cells hold more numbers than the " +
                        std::to_string(size) + " CELLS declares");
              for (std::int64_t v = 0; v < k; ++v)
                cell_points[c].push_back(point_index(c));
            }
          if (read != size)
            in.fail("the cells hold " + std::to_string(read) +
                    " numbers, but CELLS declares " + std::to_string(size));
        }

        // Version 5: OFFSETS then CONNECTIVITY.
        void
        cells_5()
        {
          check_no_cells();
          const std::uint64_t n_offsets = in.count("the number of offsets", 1);
          const std::uint64_t n_connectivity =
            in.count("the size of the connectivity", 1);
          if (n_offsets == 0)
            in.fail("CELLS declares no offsets (there must be one more than "
                    "cells)");
          in.expect("OFFSETS");
          in.word("the offsets' data type");
          std::vector<std::uint64_t> offsets(n_offsets);
          for (std::uint64_t i = 0; i < n_offsets; ++i)
            {
              offsets[i] = in.integer("an offset", 0, n_connectivity);
              if ((i == 0 && offsets[i] != 0) ||
                  (i > 0 && (offsets[i] < offsets[i - 1] ||
                             offsets[i] - offsets[i - 1] > 64)))
                in.fail("offset " + std::to_string(i) + " is " +
                        std::to_string(offsets[i]) +
                        ": offsets start at 0 and grow by at most 64");
            }
          if (offsets.back() != n_connectivity)
            in.fail("the offsets end at " + std::to_string(offsets.back()) +
                    " but CELLS declares " + std::to_string(n_connectivity) +
                    " connectivity entries");
          in.expect("CONNECTIVITY");
          in.word("the connectivity's data type");
          const std::uint64_t n = n_offsets - 1;
          cell_points.resize(n);
          cell_lines.resize(n);
          for (std::uint64_t c = 0; c < n; ++c)
            for (std::uint64_t v = offsets[c]; v < offsets[c + 1]; ++v)
              {
                cell_points[c].push_back(point_index(c));
                cell_lines[c] = in.line();
              }
        }

        void
        cell_types()
        {
          if (have_types)
            in.fail("a second CELL_TYPES section");
          const std::uint64_t n = in.count("the number of cell types", 1);
          if (n != cell_points.size())
            in.fail("CELL_TYPES lists " + std::to_string(n) +
                    " cells, but CELLS " + std::to_string(cell_points.size()));
          types.resize(n);
          for (std::uint64_t c = 0; c < n; ++c)
            {
              types[c]                    = in.integer("a cell type", 0, 255);
              const std::int64_t t        = types[c];
              const std::size_t  k        = cell_points[c].size();
              const std::size_t  expected = t == 10 ? 4 :
                                            t == 5  ? 3 :
                                            t == 3  ? 2 :
                                            t == 1  ? 1 :
                                                      0;
              if (expected == 0)
                in.fail("cell " + std::to_string(c) + " has VTK type " +
                        std::to_string(t) +
                        "; softface needs tetrahedra (type 10), with "
                        "triangles (5), lines (3) and vertices (1) allowed");
              if (k != expected)
                in.fail("cell " + std::to_string(c) + " has VTK type " +
                        std::to_string(t) + " but " + std::to_string(k) +
                        " points (type " + std::to_string(t) + " has " +
                        std::to_string(expected) + ")");
            }
          have_types = true;
        }

        // Values of one array of n_tuples x n_components: the ids if @p keep
        // (checked whole numbers), else read past unparsed.
        void
        array_values(const std::string  &name,
                     const std::uint64_t n_tuples,
                     const std::uint64_t n_components,
                     const bool          keep)
        {
          if (keep && n_components != 1)
            in.fail("the cell data '" + name + "' has " +
                    std::to_string(n_components) + " components, not 1");
          if (n_tuples * n_components > in.count_limit())
            in.fail("the data '" + name +
                    "' holds more values than the rest of the file can");
          const std::string what = "a value of '" + name + "'";
          for (std::uint64_t i = 0; i < n_tuples * n_components; ++i)
            {
              if (!keep)
                {
                  in.word(what);
                  continue;
                }
              const double value = in.real(what);
              if (!(value >= 0 && value <= max_id &&
                    value == std::floor(value)))
                in.fail("cell " + std::to_string(i) + " has " + name + " " +
                        number_text(value) +
                        "; ids must be whole numbers from 0 to " +
                        std::to_string(std::int64_t(max_id)));
              ids.push_back(value);
            }
        }

        // CELL_DATA or POINT_DATA: its arrays up to the next such section.
        // The ids are the first cell array with an id name.
        void
        data_section(const bool cells)
        {
          const std::string   section = cells ? "CELL_DATA" : "POINT_DATA";
          const std::uint64_t n       = in.count("the size of " + section, 1);
          const std::uint64_t expected =
            cells ? cell_points.size() : data.vertices.size();
          if (n != expected)
            in.fail(section + " lists " + std::to_string(n) + " " +
                    (cells ? "cells" : "points") + ", but the mesh has " +
                    std::to_string(expected));
          while (!in.at_end() && !in.next_is("CELL_DATA") &&
                 !in.next_is("POINT_DATA"))
            {
              const std::string kind(in.word("a data array"));
              const auto        keep = [&](const std::string &name) {
                return cells && is_id_name(name) && ids.empty();
              };
              if (kind == "SCALARS")
                {
                  const std::string name(in.word("the array's name"));
                  in.word("the array's data type");
                  // An optional component count, then LOOKUP_TABLE.
                  std::string   next(in.word("LOOKUP_TABLE"));
                  std::uint64_t components = 1;
                  if (next != "LOOKUP_TABLE")
                    {
                      const auto c = std::strtoll(next.c_str(), nullptr, 10);
                      if (c < 1 || c > 4 || next != std::to_string(c))
                        in.fail("expected a component count (1 to 4) or "
                                "LOOKUP_TABLE but found '" +
                                next.substr(0, 40) + "'");
                      components = c;
                      in.expect("LOOKUP_TABLE");
                    }
                  in.word("the lookup table's name");
                  array_values(name, n, components, keep(name));
                }
              else if (kind == "VECTORS" || kind == "NORMALS" ||
                       kind == "TENSORS")
                {
                  const std::string name(in.word("the array's name"));
                  in.word("the array's data type");
                  array_values(name, n, kind == "TENSORS" ? 9 : 3, false);
                }
              else if (kind == "TEXTURE_COORDINATES")
                {
                  const std::string  name(in.word("the array's name"));
                  const std::int64_t dim = in.integer("a dimension", 1, 3);
                  in.word("the array's data type");
                  array_values(name, n, dim, false);
                }
              else if (kind == "COLOR_SCALARS")
                {
                  const std::string  name(in.word("the array's name"));
                  const std::int64_t m = in.integer("a value count", 1, 4);
                  array_values(name, n, m, false);
                }
              else if (kind == "LOOKUP_TABLE")
                {
                  const std::string   name(in.word("the table's name"));
                  const std::uint64_t size = in.count("a table size", 4);
                  array_values(name, size, 4, false);
                }
              else if (kind == "FIELD")
                field(cells);
              else if (kind == "METADATA")
                metadata();
              else
                in.fail("unexpected '" + kind.substr(0, 40) + "' in " +
                        section);
            }
        }

        // FIELD data: of the dataset (e.g. TIME), of the cells or points.
        void
        field(const bool cells)
        {
          in.word("the field's name");
          const std::uint64_t n = in.count("the number of field arrays", 4);
          for (std::uint64_t a = 0; a < n; ++a)
            {
              const std::string   name(in.word("the array's name"));
              const std::uint64_t components =
                in.count("the array's component count", 1);
              const std::uint64_t tuples =
                in.count("the array's tuple count", 1);
              in.word("the array's data type");
              const bool keep = cells && is_id_name(name) && ids.empty();
              if (keep && tuples != cell_points.size())
                in.fail("the field array '" + name + "' has " +
                        std::to_string(tuples) + " tuples for " +
                        std::to_string(cell_points.size()) + " cells");
              array_values(name, tuples, components, keep);
              if (in.next_is("METADATA"))
                {
                  in.word("METADATA");
                  metadata();
                }
            }
        }

        // VTK 9 writes METADATA blocks ended by an empty line.
        void
        metadata()
        {
          in.skip_to_empty_line();
        }

        MeshData
        build()
        {
          if (!ids.empty() && ids.size() != cell_points.size())
            in.fail("the ids cover " + std::to_string(ids.size()) +
                    " cells of " + std::to_string(cell_points.size()));
          for (std::size_t c = 0; c < cell_points.size(); ++c)
            {
              const MeshData::Origin origin{std::int64_t(c), cell_lines[c]};
              const unsigned int     id = ids.empty() ? 0 : ids[c];
              if (types[c] == 10)
                data.add_tetrahedron(cell_points[c], id, origin);
              else if (types[c] == 5)
                data.add_triangle(cell_points[c], id, origin);
            }
          return std::move(data);
        }
      };
    } // namespace

    MeshData
    read_legacy_vtk(const std::string &filename)
    {
      return VtkReader(filename).read();
    }
  } // namespace Mesh
} // namespace softface

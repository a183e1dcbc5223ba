// Reads VTK XML UnstructuredGrid (.vtu) mesh files for Scene's "Mesh file",
// as ParaView, VTK, meshio or a parallel writer save them: the XML is parsed
// with Boost.PropertyTree, the DataArrays are decoded from ascii, base64 or
// raw appended bytes (zlib or not), and every <Piece> is merged into one
// tetrahedral triangulation. Called by io/mesh_reader.cc for every .vtu that
// is not deal.II's own serialisation. Whatever cannot be read completely is
// refused with one softface::Error.

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>

#include <softface/core/error.h>
#include <softface/io/mesh_data.h>
#include <softface/io/vtu_reader.h>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <memory>
#include <numeric>
#include <sstream>

namespace softface
{
  namespace Mesh
  {
    namespace
    {
      using boost::property_tree::ptree;

      // VTK files nest five elements deep; the XML parser recurses once per
      // level, so a hostile file nested much deeper would overflow the stack.
      constexpr unsigned int max_xml_depth = 64;

      // Deflate shrinks data by at most about 1032:1: a zlib block header
      // that claims more is corrupt, and nothing is allocated for it.
      constexpr std::uint64_t max_zlib_ratio = 1032;

      std::string
      number_text(const double value)
      {
        std::ostringstream s;
        s << std::setprecision(15) << value;
        return s.str();
      }

      std::string
      attribute(const ptree       &node,
                const std::string &name,
                const std::string &fallback = "")
      {
        return node.get("<xmlattr>." + name, fallback);
      }

      std::uint64_t
      whole_number(const std::string &text, const std::string &what)
      {
        if (text.empty())
          throw Error(what + " is missing");
        std::uint64_t value  = 0;
        const char   *end    = text.data() + text.size();
        const auto    result = std::from_chars(text.data(), end, value);
        if (result.ec != std::errc() || result.ptr != end)
          throw Error(what + " '" + text + "' is not a whole number");
        return value;
      }

      bool
      is_index(const double value, const double limit)
      {
        return value >= 0 && value < limit && value == std::floor(value);
      }

      // The end ('>') of the tag that starts at @p begin, skipping quoted
      // attribute values.
      std::size_t
      end_of_tag(const std::string &text, const std::size_t begin)
      {
        char quote = 0;
        for (std::size_t i = begin; i < text.size(); ++i)
          if (quote != 0)
            quote = (text[i] == quote) ? 0 : quote;
          else if (text[i] == '"' || text[i] == '\'')
            quote = text[i];
          else if (text[i] == '>')
            return i;
        return std::string::npos;
      }

      void
      check_nesting(const std::string &xml)
      {
        unsigned int depth = 0;
        std::size_t  i     = xml.find('<');
        while (i != std::string::npos)
          {
            const char  next = (i + 1 < xml.size()) ? xml[i + 1] : 0;
            std::size_t end;
            if (xml.compare(i, 4, "<!--") == 0)
              end = xml.find("-->", i);
            else if (xml.compare(i, 9, "<![CDATA[") == 0)
              end = xml.find("]]>", i);
            else
              {
                end = end_of_tag(xml, i);
                if (end == std::string::npos)
                  break; // the parser says what is wrong
                if (next == '/')
                  depth -= (depth > 0);
                else if (next != '!' && next != '?' && xml[end - 1] != '/' &&
                         ++depth > max_xml_depth)
                  throw Error("its XML is nested more than " +
                              std::to_string(max_xml_depth) + " levels deep");
              }
            i = (end == std::string::npos) ? end : xml.find('<', end);
          }
      }

      // @p xml (emptied, to free its memory before the tree grows) into
      // @p tree; a parse error names its line.
      void
      parse_xml(std::string &xml, ptree &tree)
      {
        check_nesting(xml);
        try
          {
            std::istringstream stream(xml);
            std::string().swap(xml);
            boost::property_tree::read_xml(
              stream, tree, boost::property_tree::xml_parser::no_comments);
          }
        catch (const boost::property_tree::xml_parser_error &e)
          {
            throw Error("malformed XML at line " + std::to_string(e.line()) +
                        ": " + e.message());
          }
      }

      // Decodes quantum by quantum, so that several concatenated base64
      // streams (VTK encodes a header and its data separately) come out as
      // one byte sequence.
      std::vector<unsigned char>
      decode_base64(const std::string &text)
      {
        std::vector<unsigned char> bytes;
        bytes.reserve(text.size() / 4 * 3);
        int quantum[4], n = 0;
        for (const char c : text)
          {
            int digit;
            if (c >= 'A' && c <= 'Z')
              digit = c - 'A';
            else if (c >= 'a' && c <= 'z')
              digit = c - 'a' + 26;
            else if (c >= '0' && c <= '9')
              digit = c - '0' + 52;
            else if (c == '+' || c == '/')
              digit = (c == '+') ? 62 : 63;
            else if (c == '=')
              digit = -1;
            else if (std::isspace(static_cast<unsigned char>(c)))
              continue;
            else
              throw Error("invalid base64 character '" + std::string(1, c) +
                          "'");
            quantum[n++] = digit;
            if (n < 4)
              continue;
            n = 0;
            if (quantum[0] < 0 || quantum[1] < 0 ||
                (quantum[2] < 0 && quantum[3] >= 0))
              throw Error("corrupt base64 padding");
            const unsigned int v = (quantum[0] << 18) | (quantum[1] << 12) |
                                   (std::max(quantum[2], 0) << 6) |
                                   std::max(quantum[3], 0);
            bytes.push_back((v >> 16) & 0xff);
            if (quantum[2] >= 0)
              bytes.push_back((v >> 8) & 0xff);
            if (quantum[3] >= 0)
              bytes.push_back(v & 0xff);
          }
        if (n != 0)
          throw Error("truncated base64 data");
        return bytes;
      }

      std::vector<double>
      parse_ascii(const std::string &text)
      {
        std::vector<double> values;
        const char *p = text.data(), *const end = p + text.size();
        const auto space = [](const char c) {
          return std::isspace(static_cast<unsigned char>(c)) != 0;
        };
        while ((p = std::find_if_not(p, end, space)) != end)
          {
            const char *const token_end = std::find_if(p, end, space);
            double            value;
            const auto        result =
              std::from_chars(p + (*p == '+'), token_end, value);
            if (result.ec != std::errc() || result.ptr != token_end)
              throw Error(
                "'" + std::string(p, std::min<std::size_t>(token_end - p, 24)) +
                "' is not a number");
            values.push_back(value);
            p = token_end;
          }
        return values;
      }

      template <typename T>
      std::vector<double>
      values_from(const std::vector<unsigned char> &bytes,
                  const std::string                &type)
      {
        if (bytes.size() % sizeof(T) != 0)
          throw Error(std::to_string(bytes.size()) +
                      " bytes are not a whole number of " + type + " values");
        std::vector<double> values(bytes.size() / sizeof(T));
        for (std::size_t i = 0; i < values.size(); ++i)
          {
            T value;
            std::memcpy(&value, bytes.data() + i * sizeof(T), sizeof(T));
            values[i] = static_cast<double>(value);
          }
        return values;
      }

      std::vector<double>
      values_from(const std::vector<unsigned char> &bytes,
                  const std::string                &type)
      {
        if (type == "Int8")
          return values_from<std::int8_t>(bytes, type);
        if (type == "UInt8")
          return values_from<std::uint8_t>(bytes, type);
        if (type == "Int16")
          return values_from<std::int16_t>(bytes, type);
        if (type == "UInt16")
          return values_from<std::uint16_t>(bytes, type);
        if (type == "Int32")
          return values_from<std::int32_t>(bytes, type);
        if (type == "UInt32")
          return values_from<std::uint32_t>(bytes, type);
        if (type == "Int64")
          return values_from<std::int64_t>(bytes, type);
        if (type == "UInt64")
          return values_from<std::uint64_t>(bytes, type);
        if (type == "Float32")
          return values_from<float>(bytes, type);
        if (type == "Float64")
          return values_from<double>(bytes, type);
        throw Error("its type '" + type + "' is not a VTK number type");
      }

      class VtuFile
      {
      public:
        explicit VtuFile(const std::string &filename)
        {
          std::ifstream in(filename, std::ios::binary);
          if (!in)
            throw Error("it cannot be opened");
          content.assign(std::istreambuf_iterator<char>(in),
                         std::istreambuf_iterator<char>());

          // Raw appended bytes are no XML: the parser gets the file without
          // what lies between <AppendedData ...> and </AppendedData>, and
          // appended arrays are decoded from the file's bytes.
          std::string       xml;
          const std::size_t appended = content.find("<AppendedData");
          if (appended == std::string::npos)
            xml.swap(content);
          else
            {
              const std::size_t tag_end = end_of_tag(content, appended);
              if (tag_end == std::string::npos)
                throw Error("its AppendedData tag is not closed");
              if (content[tag_end - 1] != '/')
                {
                  const std::size_t close = content.rfind("</AppendedData>");
                  if (close == std::string::npos || close < tag_end)
                    throw Error("it has no </AppendedData> (truncated?)");
                  const std::size_t underscore =
                    content.find_first_not_of(" \t\r\n", tag_end + 1);
                  if (underscore < close && content[underscore] == '_')
                    {
                      appended_begin = underscore + 1;
                      appended_end   = close;
                    }
                  xml = content.substr(0, tag_end + 1) + content.substr(close);
                }
              else
                xml = content;
            }

          parse_xml(xml, tree);

          const auto file = tree.get_child_optional("VTKFile");
          if (!file || attribute(*file, "type") != "UnstructuredGrid")
            throw Error("it is not a VTK UnstructuredGrid file");
          const std::string compressor = attribute(*file, "compressor");
          compressed                   = !compressor.empty();
          if (compressed && compressor != "vtkZLibDataCompressor")
            throw Error("compressor '" + compressor +
                        "' is not supported (only vtkZLibDataCompressor)");
          const std::string header_type =
            attribute(*file, "header_type", "UInt32");
          if (header_type != "UInt32" && header_type != "UInt64")
            throw Error("header_type '" + header_type +
                        "' is not supported (UInt32 or UInt64)");
          header_size = (header_type == "UInt64") ? 8 : 4;
          byte_order  = attribute(*file, "byte_order", "LittleEndian");

          const auto grid = file->get_child_optional("UnstructuredGrid");
          if (!grid)
            throw Error("it has no UnstructuredGrid element");
          if (const auto data = file->get_child_optional("AppendedData"))
            {
              const std::string encoding = attribute(*data, "encoding");
              if (encoding != "raw")
                throw Error("its appended data are encoded '" + encoding +
                            "' (softface reads raw appended data; save as "
                            "'binary' or 'ascii' otherwise)");
              if (appended_begin == std::string::npos)
                throw Error("its appended data do not start with '_'");
            }
        }

        const ptree &
        grid() const
        {
          return tree.get_child("VTKFile.UnstructuredGrid");
        }

        // The values of a DataArray, whatever its format; errors name it.
        std::vector<double>
        values(const ptree &array, const std::string &name) const
        {
          try
            {
              const std::string format = attribute(array, "format", "ascii");
              if (format == "ascii")
                return parse_ascii(array.data());
              if (format != "binary" && format != "appended")
                throw Error("its format '" + format +
                            "' is not ascii, binary or appended");
              if (byte_order != "LittleEndian")
                throw Error("the file's byte_order is '" + byte_order +
                            "' (softface reads LittleEndian binary data)");
              const std::string type = attribute(array, "type");
              if (format == "binary")
                {
                  const auto raw = decode_base64(array.data());
                  return values_from(unpack(raw.data(), raw.size()), type);
                }
              if (appended_begin == std::string::npos)
                throw Error("it is appended but the file has no raw "
                            "AppendedData");
              const std::uint64_t offset =
                whole_number(attribute(array, "offset"), "its offset");
              const std::size_t size = appended_end - appended_begin;
              if (offset > size)
                throw Error("its offset " + std::to_string(offset) +
                            " is past the end of the appended data");
              const auto *start = reinterpret_cast<const unsigned char *>(
                content.data() + appended_begin + offset);
              return values_from(unpack(start, size - offset), type);
            }
          catch (const Error &e)
            {
              throw Error("DataArray '" + name + "': " + e.what());
            }
        }

      private:
        // Strips the block header (and inflates zlib blocks) of the binary
        // data that @p size bytes from @p raw hold, checking every size in
        // the header against the bytes actually there.
        std::vector<unsigned char>
        unpack(const unsigned char *raw, const std::size_t size) const
        {
          const std::size_t h      = header_size;
          const auto        header = [&](const std::uint64_t i) {
            if (i >= size / h)
              throw Error("truncated data block header");
            if (h == 8)
              {
                std::uint64_t value;
                std::memcpy(&value, raw + i * h, h);
                return value;
              }
            std::uint32_t value;
            std::memcpy(&value, raw + i * h, h);
            return std::uint64_t(value);
          };

          if (!compressed)
            {
              const std::uint64_t n = header(0);
              if (n > size - h)
                throw Error("the data block of " + std::to_string(n) +
                            " bytes is truncated");
              return {raw + h, raw + h + n};
            }

          const std::uint64_t n_blocks   = header(0);
          const std::uint64_t block_size = header(1);
          const std::uint64_t last_size  = header(2);
          if (n_blocks > size / h)
            throw Error("truncated zlib block header");
          std::uint64_t              position = (3 + n_blocks) * h;
          std::vector<unsigned char> data;
          for (std::uint64_t b = 0; b < n_blocks; ++b)
            {
              const std::uint64_t compressed_size = header(3 + b);
              const std::uint64_t expected =
                (b + 1 == n_blocks && last_size != 0) ? last_size : block_size;
              if (position > size || compressed_size > size - position)
                throw Error("truncated zlib block");
              if (expected > max_zlib_ratio * compressed_size + 64)
                throw Error("corrupt zlib block header");
              const std::size_t old = data.size();
              data.resize(old + expected);
              // The block must fill exactly the sizes its header gives.
              uLongf inflated = expected;
              uLong  consumed = compressed_size;
              if (uncompress2(data.data() + old,
                              &inflated,
                              raw + position,
                              &consumed) != Z_OK ||
                  inflated != expected || consumed != compressed_size)
                throw Error("corrupt zlib block");
              position += compressed_size;
            }
          return data;
        }

        std::string content; // the whole file
        ptree       tree;
        bool        compressed  = false;
        std::size_t header_size = 4;
        std::string byte_order;
        std::size_t appended_begin = std::string::npos; // after the '_'
        std::size_t appended_end   = std::string::npos;
      };

      // The first DataArray in @p section that @p accept takes by its Name,
      // or nullptr.
      template <typename Accept>
      const ptree *
      find_array(const ptree &piece, const std::string &section, Accept accept)
      {
        if (const auto s = piece.get_child_optional(section))
          for (const auto &child : *s)
            if (child.first == "DataArray" &&
                accept(attribute(child.second, "Name")))
              return &child.second;
        return nullptr;
      }

      bool
      is_id_name(const std::string &name)
      {
        return name == "MaterialID" || name == "material_id" ||
               name == "gmsh:physical" || name == "CellEntityIds";
      }

      // Everything of one piece, with point numbers relative to the piece.
      struct Piece
      {
        std::vector<Point<3>>    points;
        std::vector<CellData<3>> cells;
        std::vector<CellData<2>> faces;
        std::string              id_name;
      };

      // The values of the DataArray named @p name in @p section, which must
      // hold one value per cell (an array may be left out if there are no
      // cells).
      std::vector<double>
      array_values(const VtuFile      &file,
                   const ptree        &piece,
                   const std::string  &section,
                   const std::string  &name,
                   const std::uint64_t n_cells)
      {
        const ptree *array =
          find_array(piece, section, [&](const auto &n) { return n == name; });
        if (array == nullptr && n_cells > 0)
          throw Error("it has no DataArray '" + name + "' in " + section);
        std::vector<double> values;
        if (array != nullptr)
          values = file.values(*array, name);
        if (values.size() != n_cells && name != "connectivity")
          throw Error("NumberOfCells is " + std::to_string(n_cells) + " but '" +
                      name + "' holds " + std::to_string(values.size()) +
                      " values");
        return values;
      }

      // The .vtu files of a parallel record (.pvtu, as write_pvtu_record()
      // and ParaView write it): its Pieces' Sources, relative to its folder.
      std::vector<std::string>
      record_sources(const std::string &filename)
      {
        std::ifstream in(filename);
        if (!in)
          throw Error("it cannot be opened");
        std::string xml((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
        ptree       tree;
        parse_xml(xml, tree);
        const auto file = tree.get_child_optional("VTKFile");
        if (!file || attribute(*file, "type") != "PUnstructuredGrid")
          throw Error("it is not a VTK PUnstructuredGrid file");
        const std::filesystem::path folder =
          std::filesystem::path(filename).parent_path();
        std::vector<std::string> sources;
        if (const auto grid = file->get_child_optional("PUnstructuredGrid"))
          for (const auto &child : *grid)
            if (child.first == "Piece")
              {
                const std::string source = attribute(child.second, "Source");
                if (source.empty())
                  throw Error("its Piece " + std::to_string(sources.size()) +
                              " has no Source");
                sources.push_back((folder / source).string());
              }
        if (sources.empty())
          throw Error("it names no Piece");
        return sources;
      }

      // The points of a piece, checked (finite, as many as it says).
      std::vector<Point<3>>
      read_points(const VtuFile &file, const ptree &piece)
      {
        const std::uint64_t n_points =
          whole_number(attribute(piece, "NumberOfPoints"), "NumberOfPoints");

        // Points: the first DataArray in <Points>, whatever its Name.
        const ptree *points_array =
          find_array(piece, "Points", [](const auto &) { return true; });
        std::vector<double> xyz;
        if (points_array != nullptr)
          {
            const std::string components =
              attribute(*points_array, "NumberOfComponents", "3");
            if (components != "3")
              throw Error("its Points have " + components +
                          " components instead of 3");
            xyz = file.values(*points_array, "Points");
          }
        if (xyz.size() % 3 != 0 || xyz.size() / 3 != n_points)
          throw Error("NumberOfPoints is " + std::to_string(n_points) +
                      " but Points holds " + std::to_string(xyz.size()) +
                      " numbers (3 per point)");
        std::vector<Point<3>> points(n_points);
        for (std::size_t i = 0; i < n_points; ++i)
          {
            for (unsigned int d = 0; d < 3; ++d)
              if (!std::isfinite(xyz[3 * i + d]))
                throw Error("point " + std::to_string(i) + " has coordinate " +
                            number_text(xyz[3 * i + d]));
              else if (std::abs(xyz[3 * i + d]) > largest_coordinate)
                throw Error("point " + std::to_string(i) +
                            " has the coordinate " +
                            far_coordinate(xyz[3 * i + d]));
            points[i] = Point<3>(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
          }
        return points;
      }

      Piece
      read_piece(const VtuFile &file, const ptree &piece)
      {
        // Both counts checked before any array, as a reader would expect.
        const std::uint64_t n_points =
          whole_number(attribute(piece, "NumberOfPoints"), "NumberOfPoints");
        const std::uint64_t n_cells =
          whole_number(attribute(piece, "NumberOfCells"), "NumberOfCells");
        Piece result;
        result.points = read_points(file, piece);
        const auto connectivity =
          array_values(file, piece, "Cells", "connectivity", n_cells);
        const auto offsets =
          array_values(file, piece, "Cells", "offsets", n_cells);
        const auto types = array_values(file, piece, "Cells", "types", n_cells);
        // Offsets are where each cell's points end in connectivity.
        const double n_entries = connectivity.size();
        double       previous  = 0;
        for (std::size_t c = 0; c < n_cells; ++c)
          {
            if (!(offsets[c] >= previous && offsets[c] <= n_entries) ||
                offsets[c] != std::floor(offsets[c]))
              throw Error("the offset of cell " + std::to_string(c) + " is " +
                          number_text(offsets[c]) +
                          ", not a whole number between the one before (" +
                          number_text(previous) + ") and the size of " +
                          "connectivity (" + number_text(n_entries) + ")");
            previous = offsets[c];
          }
        if (previous != n_entries)
          throw Error("the offsets end at " + number_text(previous) +
                      " but connectivity holds " + number_text(n_entries) +
                      " entries");

        std::vector<double> ids, ghost;
        if (const ptree *array = find_array(piece, "CellData", is_id_name))
          {
            result.id_name = attribute(*array, "Name");
            ids =
              array_values(file, piece, "CellData", result.id_name, n_cells);
          }
        // Cells that a parallel writer copied from another piece.
        if (find_array(piece, "CellData", [](const auto &n) {
              return n == "vtkGhostType";
            }) != nullptr)
          ghost =
            array_values(file, piece, "CellData", "vtkGhostType", n_cells);

        for (std::size_t c = 0; c < n_cells; ++c)
          {
            const std::size_t begin = (c == 0) ? 0 : offsets[c - 1];
            const std::size_t n     = std::size_t(offsets[c]) - begin;
            const double      type  = types[c];
            const std::string cell  = "cell " + std::to_string(c);
            const bool duplicate = !ghost.empty() && is_index(ghost[c], 256) &&
                                   (unsigned(ghost[c]) & 1) != 0;
            if (type == 1 || type == 3 || duplicate)
              continue;
            if (type != 10 && type != 5)
              throw Error(cell + " has VTK type " + number_text(type) +
                          "; softface needs tetrahedra (type 10)");
            const std::string what =
              (type == 10) ? "a tetrahedron" : "a triangle";
            const unsigned int n_vertices = (type == 10) ? 4 : 3;
            if (n != n_vertices)
              throw Error(cell + " (" + what + ") has " + std::to_string(n) +
                          " points");
            std::vector<unsigned int> vertices(n_vertices);
            for (unsigned int v = 0; v < n_vertices; ++v)
              {
                const double index = connectivity[begin + v];
                if (!is_index(index, n_points))
                  throw Error(cell + " (" + what + ") refers to point " +
                              number_text(index) + ", but the piece has " +
                              std::to_string(n_points) + " points");
                vertices[v] = index;
              }
            const double id = ids.empty() ? 0 : ids[c];
            if (!is_index(id, 256))
              throw Error(cell + " has " + result.id_name + " " +
                          number_text(id) +
                          "; ids must be whole numbers from 0 to 255");
            if (type == 10)
              {
                result.cells.emplace_back(4);
                result.cells.back().vertices    = vertices;
                result.cells.back().material_id = id;
              }
            else
              {
                result.faces.emplace_back(3);
                result.faces.back().vertices    = vertices;
                result.faces.back().boundary_id = id;
              }
          }
        return result;
      }

      // A parallel writer repeats the points on the interfaces between
      // pieces, with exactly the same coordinates: each of them is merged
      // with the coincident points of other pieces, so that the mesh conforms
      // there. Coincident points within one piece stay as the file has them
      // (they may be meant to be disconnected).
      void
      merge_across_pieces(const std::vector<Point<3>>     &vertices,
                          const std::vector<unsigned int> &piece_of_vertex,
                          std::vector<CellData<3>>        &cells,
                          SubCellData                     &faces)
      {
        std::vector<unsigned int> order(vertices.size());
        std::iota(order.begin(), order.end(), 0u);
        std::sort(order.begin(),
                  order.end(),
                  [&](const unsigned int a, const unsigned int b) {
                    for (unsigned int d = 0; d < 3; ++d)
                      if (vertices[a][d] != vertices[b][d])
                        return vertices[a][d] < vertices[b][d];
                    return a < b;
                  });
        std::vector<unsigned int> merged(vertices.size());
        std::iota(merged.begin(), merged.end(), 0u);
        for (std::size_t i = 0; i < order.size();)
          {
            std::size_t end = i + 1;
            while (end < order.size() &&
                   vertices[order[end]] == vertices[order[i]])
              ++end;
            if (piece_of_vertex[order[i]] != piece_of_vertex[order[end - 1]])
              for (std::size_t j = i + 1; j < end; ++j)
                merged[order[j]] = order[i];
            i = end;
          }
        for (auto &cell : cells)
          for (unsigned int &v : cell.vertices)
            v = merged[v];
        for (auto &face : faces.boundary_quads)
          for (unsigned int &v : face.vertices)
            v = merged[v];
      }
      /// Every Piece of a .vtu file, or of the .vtu files a parallel
      /// record (.pvtu) names, in order.
      struct Pieces
      {
        explicit Pieces(const std::string &filename)
            : record(filename.size() > 5 &&
                     filename.compare(filename.size() - 5, 5, ".pvtu") == 0)
        {
          // A parallel record's pieces are in files of their own.
          const std::vector<std::string> sources =
            record ? record_sources(filename) :
                     std::vector<std::string>{filename};
          for (const std::string &source : sources)
            {
              try
                {
                  files.push_back(std::make_unique<VtuFile>(source));
                }
              catch (const std::exception &e)
                {
                  // A piece that is a folder fails in the stream library.
                  if (!record)
                    throw;
                  throw Error("its piece '" + source +
                              "': " + error_message(e));
                }
              for (const auto &child : files.back()->grid())
                if (child.first == "Piece")
                  {
                    file.push_back(files.back().get());
                    piece.push_back(&child.second);
                    source_of.push_back(record ? source : "");
                  }
            }
          if (piece.empty())
            throw Error("it has no Piece");
        }

        std::size_t
        size() const
        {
          return piece.size();
        }

        /// @p e, raised by piece @p p, naming the piece.
        [[noreturn]] void
        rethrow(const unsigned int p, const Error &e) const
        {
          if (!source_of[p].empty())
            throw Error("its piece '" + source_of[p] + "': " + e.what());
          if (size() == 1)
            throw e;
          throw Error("piece " + std::to_string(p) + ": " + e.what());
        }

        const bool                            record;
        std::vector<std::unique_ptr<VtuFile>> files;
        std::vector<const VtuFile *>          file;
        std::vector<const ptree *>            piece;
        std::vector<std::string>              source_of; // a record's files
      };
    } // namespace

    CellNamer
    read_vtu(const std::string &filename, Triangulation<3> &triangulation)
    {
      MeshData data;
      try
        {
          const Pieces pieces(filename);

          std::vector<Point<3>>     vertices;
          std::vector<unsigned int> piece_of_vertex;
          std::vector<CellData<3>>  cells;
          SubCellData               faces;
          std::string               id_name;
          bool                      have_id_name = false;
          for (unsigned int p = 0; p < pieces.size(); ++p)
            {
              Piece piece;
              try
                {
                  piece = read_piece(*pieces.file[p], *pieces.piece[p]);
                  // All pieces must name their ids alike (empty ones aside),
                  // or some cells would silently get id 0.
                  const auto described = [](const std::string &name) {
                    return name.empty() ? std::string("missing") :
                                          "in '" + name + "'";
                  };
                  const bool empty = piece.cells.empty() && piece.faces.empty();
                  if (!empty && have_id_name && piece.id_name != id_name)
                    throw Error("its cell ids are " + described(piece.id_name) +
                                " but those of the pieces before it are " +
                                described(id_name));
                  if (!empty)
                    {
                      id_name      = piece.id_name;
                      have_id_name = true;
                    }
                }
              catch (const Error &e)
                {
                  pieces.rethrow(p, e);
                }

              // Point numbers relative to the piece become global ones.
              const std::size_t first = vertices.size();
              if (piece.points.size() >= numbers::invalid_unsigned_int - first)
                throw Error("it has too many points");
              vertices.insert(vertices.end(),
                              piece.points.begin(),
                              piece.points.end());
              piece_of_vertex.resize(vertices.size(), p);
              for (auto &cell : piece.cells)
                {
                  for (unsigned int &v : cell.vertices)
                    v += first;
                  cells.push_back(cell);
                }
              for (auto &face : piece.faces)
                {
                  for (unsigned int &v : face.vertices)
                    v += first;
                  faces.boundary_quads.push_back(face);
                }
            }
          if (cells.empty())
            throw Error("no tetrahedra");

          if (pieces.size() > 1)
            merge_across_pieces(vertices, piece_of_vertex, cells, faces);
          data.vertices = std::move(vertices);
          data.cells    = std::move(cells);
          data.faces    = std::move(faces);
        }
      catch (const std::exception &e)
        {
          throw Error("Cannot read mesh file '" + filename +
                      "': " + error_message(e) + ".");
        }
      // Tetrahedra and triangles numbered in the order of the file.
      data.element_word = "cell";
      for (std::size_t c = 0; c < data.cells.size(); ++c)
        data.cell_origins.push_back({std::int64_t(c), 0});
      for (std::size_t f = 0; f < data.faces.boundary_quads.size(); ++f)
        data.face_origins.push_back({std::int64_t(f), 0});
      return build_triangulation(data, filename, triangulation);
    }

    PointField
    read_vtu_point_field(const std::string &filename, const std::string &name)
    {
      PointField field;
      try
        {
          const Pieces pieces(filename);
          for (unsigned int p = 0; p < pieces.size(); ++p)
            try
              {
                const VtuFile &file  = *pieces.file[p];
                const ptree   &piece = *pieces.piece[p];
                // The points as read_vtu() reads them (a piece without
                // cells may have none).
                const std::vector<Point<3>> points = read_points(file, piece);
                const ptree                *array =
                  find_array(piece, "PointData", [&](const auto &n) {
                    return n == name;
                  });
                if (array == nullptr)
                  {
                    if (points.empty())
                      continue;
                    throw Error("it has no DataArray '" + name +
                                "' in PointData");
                  }
                const std::uint64_t components =
                  whole_number(attribute(*array, "NumberOfComponents", "1"),
                               "NumberOfComponents of '" + name + "'");
                // (9: a 3x3 tensor, the most VTK's own filters write.)
                if (components < 1 || components > 9)
                  throw Error("its DataArray '" + name + "' has " +
                              std::to_string(components) +
                              " components (softface reads 1 to 9)");
                if (field.n_components != 0 && components != field.n_components)
                  throw Error("its DataArray '" + name + "' has " +
                              std::to_string(components) +
                              " components, the pieces before it " +
                              std::to_string(field.n_components));
                const std::vector<double> values = file.values(*array, name);
                if (values.size() != components * points.size())
                  throw Error("'" + name + "' holds " +
                              std::to_string(values.size()) + " values for " +
                              std::to_string(points.size()) + " points of " +
                              std::to_string(components) + " components");
                field.n_components = components;
                field.points.insert(field.points.end(),
                                    points.begin(),
                                    points.end());
                field.values.insert(field.values.end(),
                                    values.begin(),
                                    values.end());
              }
            catch (const Error &e)
              {
                pieces.rethrow(p, e);
              }
        }
      catch (const std::exception &e)
        {
          throw Error("Cannot read '" + name + "' from '" + filename +
                      "': " + error_message(e) + ".");
        }
      return field;
    }
  } // namespace Mesh
} // namespace softface

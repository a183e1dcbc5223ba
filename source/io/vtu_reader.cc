#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>

#include <softface/core/error.h>
#include <softface/io/vtu_reader.h>

#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace softface
{
  namespace Mesh
  {
    namespace
    {
      struct DataArray
      {
        std::map<std::string, std::string> attributes;
        std::string                        text; // between the tags
      };

      std::map<std::string, std::string>
      parse_attributes(const std::string &tag)
      {
        std::map<std::string, std::string> attributes;
        std::size_t                        p = 0;
        while ((p = tag.find('=', p)) != std::string::npos)
          {
            std::size_t name_end = p, name_begin = p;
            while (name_begin > 0 && !std::isspace(tag[name_begin - 1]))
              --name_begin;
            const char        quote = tag[p + 1];
            const std::size_t close = tag.find(quote, p + 2);
            if ((quote != '"' && quote != '\'') || close == std::string::npos)
              break;
            attributes[tag.substr(name_begin, name_end - name_begin)] =
              tag.substr(p + 2, close - p - 2);
            p = close + 1;
          }
        return attributes;
      }

      // Decodes quantum by quantum, so that several concatenated base64
      // streams (VTK encodes a header and its data separately) come out as
      // one byte sequence.
      std::vector<unsigned char>
      decode_base64(const std::string &text)
      {
        static const std::string alphabet =
          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        std::vector<unsigned char> bytes;
        int                        quantum[4], n = 0;
        for (const char c : text)
          {
            if (std::isspace(c))
              continue;
            const std::size_t digit = alphabet.find(c);
            if (c != '=' && digit == std::string::npos)
              throw Error("invalid base64 character");
            quantum[n++] = (c == '=') ? -1 : int(digit);
            if (n < 4)
              continue;
            n                    = 0;
            const unsigned int v = (quantum[0] << 18) | (quantum[1] << 12) |
                                   ((quantum[2] < 0 ? 0 : quantum[2]) << 6) |
                                   (quantum[3] < 0 ? 0 : quantum[3]);
            bytes.push_back((v >> 16) & 0xff);
            if (quantum[2] >= 0)
              bytes.push_back((v >> 8) & 0xff);
            if (quantum[3] >= 0)
              bytes.push_back(v & 0xff);
          }
        return bytes;
      }

      std::size_t
      size_of(const std::string &type)
      {
        if (type == "Int8" || type == "UInt8")
          return 1;
        if (type == "Int16" || type == "UInt16")
          return 2;
        if (type == "Int32" || type == "UInt32" || type == "Float32")
          return 4;
        if (type == "Int64" || type == "UInt64" || type == "Float64")
          return 8;
        throw Error("unknown DataArray type '" + type + "'");
      }

      double
      value_at(const unsigned char *p, const std::string &type)
      {
#define SOFTFACE_VTU_TYPE(name, ctype) \
  if (type == name)                    \
    {                                  \
      ctype v;                         \
      std::memcpy(&v, p, sizeof(v));   \
      return static_cast<double>(v);   \
    }
        SOFTFACE_VTU_TYPE("Int8", std::int8_t)
        SOFTFACE_VTU_TYPE("UInt8", std::uint8_t)
        SOFTFACE_VTU_TYPE("Int16", std::int16_t)
        SOFTFACE_VTU_TYPE("UInt16", std::uint16_t)
        SOFTFACE_VTU_TYPE("Int32", std::int32_t)
        SOFTFACE_VTU_TYPE("UInt32", std::uint32_t)
        SOFTFACE_VTU_TYPE("Int64", std::int64_t)
        SOFTFACE_VTU_TYPE("UInt64", std::uint64_t)
        SOFTFACE_VTU_TYPE("Float32", float)
        SOFTFACE_VTU_TYPE("Float64", double)
#undef SOFTFACE_VTU_TYPE
        throw Error("unknown DataArray type '" + type + "'");
      }

      class VtuFile
      {
      public:
        explicit VtuFile(const std::string &filename)
        {
          std::ifstream      in(filename, std::ios::binary);
          std::ostringstream s;
          s << in.rdbuf();
          content = s.str();

          const auto file_tag = tag_attributes("<VTKFile");
          if (file_tag.count("type") == 0 ||
              file_tag.at("type") != "UnstructuredGrid")
            throw Error("not a VTK UnstructuredGrid file");
          compressed =
            file_tag.count("compressor") && !file_tag.at("compressor").empty();
          if (compressed &&
              file_tag.at("compressor") != "vtkZLibDataCompressor")
            throw Error("compressor '" + file_tag.at("compressor") +
                        "' is not supported (only zlib)");
          header_type = file_tag.count("header_type") ?
                          file_tag.at("header_type") :
                          "UInt32";
          if (file_tag.count("byte_order") &&
              file_tag.at("byte_order") != "LittleEndian")
            throw Error("only LittleEndian files are supported");

          const std::size_t appended = content.find("<AppendedData");
          if (appended != std::string::npos)
            {
              const auto attributes = parse_attributes(
                content.substr(appended,
                               content.find('>', appended) - appended));
              if (attributes.count("encoding") &&
                  attributes.at("encoding") != "raw")
                throw Error("appended data must be raw-encoded (save as "
                            "'binary' or 'ascii' otherwise)");
              appended_start = content.find('_', appended) + 1;
              xml_end        = appended;
            }
        }

        std::map<std::string, std::string>
        tag_attributes(const std::string &tag) const
        {
          const std::size_t p = content.find(tag);
          if (p == std::string::npos)
            throw Error("no " + tag.substr(1) + " element");
          return parse_attributes(content.substr(p, content.find('>', p) - p));
        }

        // The DataArrays inside the first <section> ... </section>.
        std::vector<DataArray>
        arrays_in(const std::string &section) const
        {
          std::vector<DataArray> arrays;
          // Only the XML part is searched: raw appended bytes may hold
          // anything.
          const std::size_t begin = content.find("<" + section);
          if (begin == std::string::npos || begin >= xml_end)
            return arrays;
          const std::size_t end = content.find("</" + section, begin);
          std::size_t       p   = begin;
          while ((p = content.find("<DataArray", p)) != std::string::npos &&
                 p < end)
            {
              const std::size_t tag_end = content.find('>', p);
              DataArray         array;
              array.attributes =
                parse_attributes(content.substr(p, tag_end - p));
              if (content[tag_end - 1] != '/')
                {
                  const std::size_t close =
                    content.find("</DataArray>", tag_end);
                  array.text = content.substr(tag_end + 1, close - tag_end - 1);
                  p          = close;
                }
              else
                p = tag_end;
              arrays.push_back(array);
            }
          return arrays;
        }

        std::vector<double>
        values(const DataArray &array) const
        {
          const std::string   type   = array.attributes.at("type");
          const std::string   format = array.attributes.count("format") ?
                                         array.attributes.at("format") :
                                         "ascii";
          std::vector<double> result;
          if (format == "ascii")
            {
              std::istringstream in(array.text);
              double             v;
              while (in >> v)
                result.push_back(v);
              return result;
            }

          std::vector<unsigned char> raw;
          if (format == "binary")
            raw = decode_base64(array.text);
          else if (format == "appended")
            {
              const std::size_t offset =
                appended_start + std::stoull(array.attributes.at("offset"));
              raw.assign(content.begin() + offset, content.end());
            }
          else
            throw Error("DataArray format '" + format + "' is not supported");

          const std::vector<unsigned char> data = unpack(raw);
          const std::size_t                size = size_of(type);
          for (std::size_t i = 0; i + size <= data.size(); i += size)
            result.push_back(value_at(&data[i], type));
          return result;
        }

      private:
        std::size_t
        header_value(const std::vector<unsigned char> &raw,
                     const std::size_t                 index) const
        {
          const std::size_t size = size_of(header_type);
          if ((index + 1) * size > raw.size())
            throw Error("truncated data block");
          return static_cast<std::size_t>(
            value_at(&raw[index * size], header_type));
        }

        // Strip the block header (and inflate zlib blocks).
        std::vector<unsigned char>
        unpack(const std::vector<unsigned char> &raw) const
        {
          const std::size_t h = size_of(header_type);
          if (!compressed)
            {
              const std::size_t n = header_value(raw, 0);
              if (h + n > raw.size())
                throw Error("truncated data block");
              return {raw.begin() + h, raw.begin() + h + n};
            }
          const std::size_t          n_blocks   = header_value(raw, 0);
          const std::size_t          block_size = header_value(raw, 1);
          const std::size_t          last_size  = header_value(raw, 2);
          std::vector<unsigned char> data;
          std::size_t                position = h * (3 + n_blocks);
          for (std::size_t b = 0; b < n_blocks; ++b)
            {
              const std::size_t compressed_size = header_value(raw, 3 + b);
              uLongf            size =
                (b + 1 == n_blocks && last_size != 0) ? last_size : block_size;
              const std::size_t old = data.size();
              data.resize(old + size);
              if (position + compressed_size > raw.size() ||
                  uncompress(
                    &data[old], &size, &raw[position], compressed_size) != Z_OK)
                throw Error("corrupt zlib block");
              data.resize(old + size);
              position += compressed_size;
            }
          return data;
        }

        std::string content;
        bool        compressed     = false;
        std::string header_type    = "UInt32";
        std::size_t appended_start = 0;
        std::size_t xml_end        = std::string::npos;
      };
    } // namespace

    void
    read_vtu(const std::string &filename, Triangulation<3> &triangulation)
    {
      try
        {
          const VtuFile     file(filename);
          const auto        piece    = file.tag_attributes("<Piece");
          const std::size_t n_points = std::stoull(piece.at("NumberOfPoints"));
          const std::size_t n_cells  = std::stoull(piece.at("NumberOfCells"));

          const auto points = file.arrays_in("Points");
          if (points.empty())
            throw Error("no Points");
          const std::vector<double> xyz = file.values(points[0]);
          if (xyz.size() != 3 * n_points)
            throw Error("Points holds " + std::to_string(xyz.size()) +
                        " numbers for " + std::to_string(n_points) + " points");
          std::vector<Point<3>> vertices(n_points);
          for (std::size_t i = 0; i < n_points; ++i)
            vertices[i] = Point<3>(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);

          std::vector<double> connectivity, offsets, types, ids;
          for (const DataArray &a : file.arrays_in("Cells"))
            {
              const std::string name =
                a.attributes.count("Name") ? a.attributes.at("Name") : "";
              if (name == "connectivity")
                connectivity = file.values(a);
              else if (name == "offsets")
                offsets = file.values(a);
              else if (name == "types")
                types = file.values(a);
            }
          for (const DataArray &a : file.arrays_in("CellData"))
            {
              const std::string name =
                a.attributes.count("Name") ? a.attributes.at("Name") : "";
              if (ids.empty() &&
                  (name == "MaterialID" || name == "material_id" ||
                   name == "gmsh:physical" || name == "CellEntityIds"))
                ids = file.values(a);
            }
          if (offsets.size() != n_cells || types.size() != n_cells)
            throw Error("Cells must hold connectivity, offsets and types for " +
                        std::to_string(n_cells) + " cells");
          if (!ids.empty() && ids.size() != n_cells)
            throw Error("the cell id array does not have one value per cell");

          std::vector<CellData<3>> cells;
          SubCellData              faces;
          for (std::size_t c = 0; c < n_cells; ++c)
            {
              const std::size_t begin = c == 0 ? 0 : offsets[c - 1];
              const std::size_t end   = offsets[c];
              const int         type  = types[c];
              if (end > connectivity.size() || begin > end)
                throw Error("cell " + std::to_string(c) +
                            " has an invalid offset");
              if (type == 10 && end - begin == 4)
                {
                  CellData<3> cell(4);
                  for (unsigned int v = 0; v < 4; ++v)
                    cell.vertices[v] = connectivity[begin + v];
                  cell.material_id = ids.empty() ? 0 : ids[c];
                  cells.push_back(cell);
                }
              else if (type == 5 && end - begin == 3)
                {
                  CellData<2> face(3);
                  for (unsigned int v = 0; v < 3; ++v)
                    face.vertices[v] = connectivity[begin + v];
                  face.boundary_id = ids.empty() ? 0 : ids[c];
                  faces.boundary_quads.push_back(face);
                }
              else if (type != 1 && type != 3)
                throw Error("cell " + std::to_string(c) + " has VTK type " +
                            std::to_string(type) +
                            "; softface needs tetrahedra (type 10)");
            }
          for (const auto &cell : cells)
            for (const unsigned int v : cell.vertices)
              if (v >= n_points)
                throw Error("a cell refers to point " + std::to_string(v) +
                            " of " + std::to_string(n_points));
          if (cells.empty())
            throw Error("no tetrahedra");

          GridTools::delete_unused_vertices(vertices, cells, faces);
          triangulation.clear();
          triangulation.create_triangulation(vertices, cells, faces);
        }
      catch (const std::exception &e)
        {
          throw Error("Cannot read mesh file '" + filename +
                      "': " + error_message(e) + ".");
        }
    }
  } // namespace Mesh
} // namespace softface

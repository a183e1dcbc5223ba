// softface's reader of gmsh .msh files (ASCII 2.x and 4.1). deal.II's
// GridIn::read_msh checks its input with debug-only assertions, so in a
// Release build a truncated or edited file can crash or hang it;
// this reader checks everything before the mesh is built.

#include <softface/io/gmsh_reader.h>
#include <softface/io/text_tokens.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace softface
{
  namespace Mesh
  {
    namespace
    {
      constexpr std::int64_t max_tag = std::numeric_limits<int>::max();
      // Material and boundary ids: deal.II's maximum is its "invalid" id.
      constexpr std::int64_t max_id =
        std::numeric_limits<types::material_id>::max() - 1;

      // Nodes per element of the gmsh types softface knows; 0: unknown.
      unsigned int
      nodes_of_type(const std::int64_t type)
      {
        switch (type)
          {
            case 1:
              return 2; // line
            case 2:
              return 3; // triangle
            case 4:
              return 4; // tetrahedron
            case 15:
              return 1; // point
            default:
              return 0;
          }
      }

      std::string
      type_name(const std::int64_t type)
      {
        static const std::map<std::int64_t, std::string> names{
          {1, "line"},
          {2, "triangle"},
          {3, "quadrangle"},
          {4, "tetrahedron"},
          {15, "point"},
          {5, "hexahedron"},
          {6, "prism"},
          {7, "pyramid"},
          {8, "second-order line"},
          {9, "second-order triangle"},
          {11, "second-order tetrahedron"},
          {29, "third-order tetrahedron"}};
        const auto n = names.find(type);
        return "type " + std::to_string(type) +
               (n == names.end() ? "" : " (" + n->second + ")");
      }

      class GmshReader
      {
      public:
        explicit GmshReader(const std::string &filename)
            : filename(filename)
            , in(filename)
        {}

        MeshData
        read()
        {
          if (in.at_end())
            in.fail("the file is empty");
          const std::string first(in.word("'$MeshFormat'"));
          if (first == "$NOD")
            return read_format_1();
          if (first != "$MeshFormat")
            in.fail("a gmsh file starts with '$MeshFormat', this one with '" +
                    first.substr(0, 40) + "'");
          const std::string  version(in.word("the format version"));
          const std::int64_t binary = in.integer("the file type", 0, 1);
          in.integer("the data size", 1, 16);
          if (binary == 1)
            in.fail("the file is binary (format " + version +
                    "); softface reads ASCII .msh files: save it with "
                    "Mesh.Binary = 0 (gmsh -bin 0)");
          if (version == "4.1")
            format = 4;
          else if (version.rfind("2", 0) == 0)
            format = 2;
          else
            in.fail("format " + version.substr(0, 20) +
                    " is not supported; softface reads gmsh formats 1, 2.2 "
                    "and 4.1 (gmsh -format msh2 or msh41)");
          in.expect("$EndMeshFormat");

          bool have_nodes = false, have_elements = false;
          while (!in.at_end())
            {
              const std::string section(in.word("a section"));
              if (section == "$Nodes")
                {
                  if (have_nodes)
                    in.fail("a second $Nodes section");
                  format == 4 ? nodes_4() : nodes_2();
                  in.expect("$EndNodes");
                  index_node_tags();
                  have_nodes = true;
                }
              else if (section == "$Elements")
                {
                  if (!have_nodes)
                    in.fail("$Elements comes before $Nodes");
                  if (have_elements)
                    in.fail("a second $Elements section");
                  format == 4 ? elements_4() : elements_2();
                  in.expect("$EndElements");
                  have_elements = true;
                }
              else if (section == "$Entities" && format == 4)
                {
                  if (have_nodes)
                    in.fail("$Entities comes after $Nodes");
                  entities();
                  in.expect("$EndEntities");
                }
              else if (section.size() > 1 && section[0] == '$' &&
                       section.rfind("$End", 0) != 0)
                in.skip_to("$End" + section.substr(1));
              else
                in.fail("expected a section ('$Name') but found '" +
                        section.substr(0, 40) + "'");
            }
          if (!have_nodes || !have_elements)
            in.fail(std::string("the file has no ") +
                    (have_nodes ? "$Elements" : "$Nodes") + " section");
          return std::move(data);
        }

      private:
        // gmsh's format 1 (deal.II's GridOut::write_msh writes it):
        // $NOD, then $ELM with "number type physical elementary n nodes".
        MeshData
        read_format_1()
        {
          nodes_2();
          in.expect("$ENDNOD");
          index_node_tags();
          in.expect("$ELM");
          const std::uint64_t n = in.count("the number of elements", 6);
          for (std::uint64_t i = 0; i < n; ++i)
            {
              const auto [number, type] = element_head();
              const std::int64_t physical =
                in.integer("a physical tag", -max_tag, max_tag);
              in.integer("an elementary tag", -max_tag, max_tag);
              const std::int64_t n_nodes = in.integer("a node count", 0, 64);
              if (n_nodes != std::int64_t(nodes_of_type(type)))
                in.fail("element " + std::to_string(number) + " of " +
                        type_name(type) + " has " + std::to_string(n_nodes) +
                        " nodes instead of " +
                        std::to_string(nodes_of_type(type)));
              add_element(number, type, physical);
            }
          in.expect("$ENDELM");
          return std::move(data);
        }

        std::string filename;
        TextTokens  in;
        int         format = 0;
        MeshData    data;
        // gmsh node tag -> index in data.vertices.
        std::unordered_map<std::int64_t, unsigned int> vertex_of_tag;
        // The same as an array when the tags are dense (gmsh numbers its
        // nodes 1..n): each element's nodes are then looked up without
        // hashing (4 per tetrahedron, 2M at 491k tetrahedra).
        std::vector<unsigned int> vertex_of_dense_tag;
        // Physical tag of each entity, by dimension (format 4).
        std::array<std::map<std::int64_t, std::int64_t>, 4> physical_of;
        bool have_entities = false;

        void
        add_node(const std::int64_t tag, const Point<3> &x)
        {
          const auto inserted = vertex_of_tag.emplace(
            tag, static_cast<unsigned int>(data.vertices.size()));
          if (!inserted.second)
            in.fail("node " + std::to_string(tag) + " is defined twice");
          data.vertices.push_back(x);
        }

        Point<3>
        coordinates()
        {
          Point<3> x;
          for (unsigned int d = 0; d < 3; ++d)
            x[d] = in.coordinate("a node coordinate");
          return x;
        }

        void
        index_node_tags()
        {
          std::int64_t largest = 0;
          for (const auto &[tag, index] : vertex_of_tag)
            largest = std::max(largest, tag);
          if (largest > 2 * static_cast<std::int64_t>(vertex_of_tag.size()))
            return;
          vertex_of_dense_tag.assign(largest + 1,
                                     numbers::invalid_unsigned_int);
          for (const auto &[tag, index] : vertex_of_tag)
            vertex_of_dense_tag[tag] = index;
        }

        unsigned int
        vertex(const std::int64_t element)
        {
          const std::int64_t tag = in.integer("a node tag", 1, max_tag);
          if (static_cast<std::uint64_t>(tag) < vertex_of_dense_tag.size() &&
              vertex_of_dense_tag[tag] != numbers::invalid_unsigned_int)
            return vertex_of_dense_tag[tag];
          const auto node = vertex_of_tag.find(tag);
          if (node == vertex_of_tag.end())
            in.fail("element " + std::to_string(element) + " refers to node " +
                    std::to_string(tag) + ", which $Nodes does not define");
          return node->second;
        }

        // Add an element of a known type whose nodes are next in the file.
        void
        add_element(const std::int64_t number,
                    const std::int64_t type,
                    const std::int64_t id)
        {
          const unsigned int        n = nodes_of_type(type);
          std::vector<unsigned int> vertices(n);
          for (unsigned int v = 0; v < n; ++v)
            vertices[v] = vertex(number);
          if (id < 0 || id > max_id)
            in.fail("element " + std::to_string(number) + " has physical tag " +
                    std::to_string(id) +
                    "; ids must be whole numbers from 0 to " +
                    std::to_string(max_id));
          const MeshData::Origin origin{number, in.line()};
          if (type == 4)
            data.add_tetrahedron(std::move(vertices), id, origin);
          else if (type == 2)
            data.add_triangle(std::move(vertices), id, origin);
        }

        // The start of an element line in formats 1 and 2: its number and
        // its (known) type.
        std::pair<std::int64_t, std::int64_t>
        element_head()
        {
          const std::int64_t number =
            in.integer("an element number", 1, max_tag);
          const std::int64_t type = in.integer("an element type", 0);
          if (nodes_of_type(type) == 0)
            check_type(type, "element " + std::to_string(number));
          return {number, type};
        }

        void
        check_type(const std::int64_t type, const std::string &whose)
        {
          if (nodes_of_type(type) == 0)
            in.fail(whose + " has element " + type_name(type) +
                    "; softface reads tetrahedra (4), triangles (2), lines "
                    "(1) and points (15) only");
        }

        void
        nodes_2()
        {
          const std::uint64_t n = in.count("the number of nodes", 4);
          data.vertices.reserve(n);
          for (std::uint64_t i = 0; i < n; ++i)
            {
              const std::int64_t tag = in.integer("a node tag", 1, max_tag);
              add_node(tag, coordinates());
            }
        }

        void
        elements_2()
        {
          const std::uint64_t n = in.count("the number of elements", 4);
          for (std::uint64_t i = 0; i < n; ++i)
            {
              const auto [number, type]   = element_head();
              const std::int64_t n_tags   = in.integer("a tag count", 0, 64);
              std::int64_t       physical = 0;
              for (std::int64_t t = 0; t < n_tags; ++t)
                {
                  const std::int64_t tag =
                    in.integer("a tag", -max_tag, max_tag);
                  if (t == 0)
                    physical = tag;
                }
              add_element(number, type, physical);
            }
        }

        void
        entities()
        {
          std::array<std::uint64_t, 4> n;
          for (unsigned int d = 0; d < 4; ++d)
            n[d] = in.count("an entity count", 5);
          for (unsigned int d = 0; d < 4; ++d)
            for (std::uint64_t i = 0; i < n[d]; ++i)
              {
                const std::int64_t tag =
                  in.integer("an entity tag", -max_tag, max_tag);
                // A point has its coordinates, others a bounding box.
                for (unsigned int c = 0; c < (d == 0 ? 3u : 6u); ++c)
                  in.real("a bounding box coordinate");
                const std::uint64_t n_physicals =
                  in.count("a physical tag count", 1);
                if (n_physicals > 1)
                  in.fail("entity " + std::to_string(tag) + " of dimension " +
                          std::to_string(d) + " has " +
                          std::to_string(n_physicals) +
                          " physical tags; softface (as deal.II) takes one");
                std::int64_t physical = 0;
                if (n_physicals == 1)
                  physical = in.integer("a physical tag", -max_tag, max_tag);
                if (!physical_of[d].emplace(tag, physical).second)
                  in.fail("entity " + std::to_string(tag) + " of dimension " +
                          std::to_string(d) + " is defined twice");
                if (d > 0)
                  {
                    const std::uint64_t n_bounding =
                      in.count("a bounding entity count", 1);
                    for (std::uint64_t b = 0; b < n_bounding; ++b)
                      in.integer("a bounding entity tag", -max_tag, max_tag);
                  }
              }
          have_entities = true;
        }

        std::int64_t
        physical_tag(const std::int64_t dim, const std::int64_t entity)
        {
          if (!have_entities)
            return 0;
          const auto p = physical_of[dim].find(entity);
          if (p == physical_of[dim].end())
            in.fail("entity " + std::to_string(entity) + " of dimension " +
                    std::to_string(dim) + " is not in $Entities");
          return p->second;
        }

        void
        nodes_4()
        {
          const std::uint64_t n_blocks =
            in.count("the number of node blocks", 4);
          const std::uint64_t n_nodes = in.count("the number of nodes", 4);
          in.integer("the smallest node tag", 0, max_tag);
          in.integer("the largest node tag", 0, max_tag);
          data.vertices.reserve(n_nodes);
          std::uint64_t read = 0;
          for (std::uint64_t b = 0; b < n_blocks; ++b)
            {
              const std::int64_t dim = in.integer("an entity dimension", 0, 3);
              in.integer("an entity tag", -max_tag, max_tag);
              const std::int64_t  parametric = in.integer("'parametric'", 0, 1);
              const std::uint64_t n = in.count("a block's node count", 4);
              if (read + n > n_nodes)
                in.fail("the node blocks hold more nodes than the " +
                        std::to_string(n_nodes) + " declared");
              std::vector<std::int64_t> tags(n);
              for (auto &tag : tags)
                tag = in.integer("a node tag", 1, max_tag);
              for (const auto tag : tags)
                {
                  add_node(tag, coordinates());
                  if (parametric == 1)
                    for (std::int64_t p = 0; p < dim; ++p)
                      in.real("a parametric coordinate");
                }
              read += n;
            }
          if (read != n_nodes)
            in.fail("the node blocks hold " + std::to_string(read) +
                    " nodes, but " + std::to_string(n_nodes) + " are declared");
        }

        void
        elements_4()
        {
          const std::uint64_t n_blocks =
            in.count("the number of element blocks", 4);
          const std::uint64_t n_elements =
            in.count("the number of elements", 2);
          in.integer("the smallest element tag", 0, max_tag);
          in.integer("the largest element tag", 0, max_tag);
          std::uint64_t read = 0;
          for (std::uint64_t b = 0; b < n_blocks; ++b)
            {
              const std::int64_t dim = in.integer("an entity dimension", 0, 3);
              const std::int64_t entity =
                in.integer("an entity tag", -max_tag, max_tag);
              const std::int64_t type = in.integer("an element type", 0);
              if (nodes_of_type(type) == 0)
                check_type(type,
                           "the element block of entity " +
                             std::to_string(entity));
              const std::int64_t type_dim = type == 4 ? 3 :
                                            type == 2 ? 2 :
                                            type == 1 ? 1 :
                                                        0;
              if (dim != type_dim)
                in.fail("an element block of dimension " + std::to_string(dim) +
                        " holds elements of " + type_name(type) +
                        ", which have dimension " + std::to_string(type_dim));
              const std::uint64_t n =
                in.count("a block's element count", 1 + nodes_of_type(type));
              if (read + n > n_elements)
                in.fail("the element blocks hold more elements than the " +
                        std::to_string(n_elements) + " declared");
              const std::int64_t id = physical_tag(dim, entity);
              for (std::uint64_t e = 0; e < n; ++e)
                add_element(in.integer("an element tag", 1, max_tag), type, id);
              read += n;
            }
          if (read != n_elements)
            in.fail("the element blocks hold " + std::to_string(read) +
                    " elements, but " + std::to_string(n_elements) +
                    " are declared");
        }
      };
    } // namespace

    MeshData
    read_gmsh(const std::string &filename)
    {
      return GmshReader(filename).read();
    }
  } // namespace Mesh
} // namespace softface

// The checks every mesh reader's result passes before deal.II builds a
// triangulation from it (deal.II's own consistency checks are debug-only
// assertions: a duplicate cell or a stray face would corrupt memory in a
// Release build instead of stopping).

#include <deal.II/grid/grid_tools.h>

#include <softface/core/cell_order.h>
#include <softface/core/error.h>
#include <softface/io/mesh_data.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <sstream>
#include <tuple>
#include <vector>

namespace softface
{
  namespace Mesh
  {
    std::string
    MeshData::name(const Origin &origin) const
    {
      return element_word + " " + std::to_string(origin.number) +
             (origin.line == 0 ? std::string() :
                                 " (line " + std::to_string(origin.line) + ")");
    }

    void
    MeshData::add_tetrahedron(std::vector<unsigned int> points,
                              const types::material_id  id,
                              const Origin             &origin)
    {
      cells.emplace_back(4);
      cells.back().vertices    = std::move(points);
      cells.back().material_id = id;
      cell_origins.push_back(origin);
    }

    void
    MeshData::add_triangle(std::vector<unsigned int> points,
                           const types::boundary_id  id,
                           const Origin             &origin)
    {
      faces.boundary_quads.emplace_back(3);
      faces.boundary_quads.back().vertices    = std::move(points);
      faces.boundary_quads.back().boundary_id = id;
      face_origins.push_back(origin);
    }

    namespace
    {
      using Triangle = std::array<unsigned int, 3>;

      // A tetrahedron's face (points sorted) and the tetrahedron.
      struct Face
      {
        Triangle    points;
        std::size_t cell;
        bool
        operator<(const Face &other) const
        {
          return std::tie(points, cell) < std::tie(other.points, other.cell);
        }
      };
    } // namespace

    void
    check_points(const std::vector<Point<3>>                    &points,
                 const std::function<void(const std::string &)> &fail)
    {
      for (std::size_t v = 0; v < points.size(); ++v)
        for (unsigned int d = 0; d < 3; ++d)
          if (!std::isfinite(points[v][d]))
            fail("point " + std::to_string(v) +
                 " has a coordinate that is not finite");
          else if (std::abs(points[v][d]) > largest_coordinate)
            fail("point " + std::to_string(v) + " has the coordinate " +
                 far_coordinate(points[v][d]));
    }

    CellNamer
    build_triangulation(MeshData          &data,
                        const std::string &filename,
                        Triangulation<3>  &triangulation)
    {
      const auto fail = [&](const std::string &message) {
        throw Error("Cannot read mesh file '" + filename + "': " + message +
                    ".");
      };
      if (data.cells.empty())
        fail("it holds no tetrahedra");
      const std::size_t n_vertices = data.vertices.size();
      check_points(data.vertices, fail);

      // The element's name is only made for a message (not per cell).
      const auto check_indices = [&](const std::vector<unsigned int> &vs,
                                     const MeshData::Origin          &origin) {
        for (const unsigned int v : vs)
          if (v >= n_vertices)
            fail(data.name(origin) + " refers to point index " +
                 std::to_string(v) + ", but there are " +
                 std::to_string(n_vertices) + " points");
        for (std::size_t i = 0; i < vs.size(); ++i)
          for (std::size_t j = 0; j < i; ++j)
            if (vs[i] == vs[j])
              fail(data.name(origin) + " names the same point twice");
      };

      // Sorting the cells' point sets and faces finds repeated cells and
      // faces shared by more than two cells in O(n log n).
      std::vector<std::pair<std::array<unsigned int, 4>, std::size_t>> sets;
      std::vector<Face>                                                faces;
      sets.reserve(data.cells.size());
      faces.reserve(4 * data.cells.size());
      for (std::size_t c = 0; c < data.cells.size(); ++c)
        {
          const auto &vs = data.cells[c].vertices;
          if (vs.size() != 4)
            fail(data.name(data.cell_origins[c]) + " is not a tetrahedron");
          check_indices(vs, data.cell_origins[c]);
          std::array<unsigned int, 4> key{{vs[0], vs[1], vs[2], vs[3]}};
          std::sort(key.begin(), key.end());
          sets.emplace_back(key, c);
          for (unsigned int f = 0; f < 4; ++f)
            {
              Triangle t{{vs[(f + 1) % 4], vs[(f + 2) % 4], vs[(f + 3) % 4]}};
              std::sort(t.begin(), t.end());
              faces.push_back({t, c});
            }
        }
      sort_by_first_point(sets, n_vertices, [](const auto &set) {
        return set.first[0];
      });
      for (std::size_t i = 1; i < sets.size(); ++i)
        if (sets[i].first == sets[i - 1].first)
          fail(data.name(data.cell_origins[sets[i].second]) +
               " has the same four points as " +
               data.name(data.cell_origins[sets[i - 1].second]));
      sort_by_first_point(faces, n_vertices, [](const Face &face) {
        return face.points[0];
      });
      for (std::size_t i = 2; i < faces.size(); ++i)
        if (faces[i].points == faces[i - 2].points)
          {
            std::ostringstream corners;
            for (unsigned int k = 0; k < 3; ++k)
              corners << (k ? ", (" : "(") << data.vertices[faces[i].points[k]]
                      << ')';
            fail("the triangle " + corners.str() +
                 " is a face of three tetrahedra (" +
                 data.name(data.cell_origins[faces[i - 2].cell]) + ", " +
                 data.name(data.cell_origins[faces[i - 1].cell]) + ", " +
                 data.name(data.cell_origins[faces[i].cell]) +
                 "); the mesh is not a manifold");
          }

      // Boundary triangles: faces of exactly one tetrahedron, each once
      // (a repeat with the same id is harmless).
      std::vector<std::pair<Triangle, std::size_t>> boundary;
      auto &triangles = data.faces.boundary_quads;
      for (std::size_t f = 0; f < triangles.size(); ++f)
        {
          check_indices(triangles[f].vertices, data.face_origins[f]);
          Triangle t{{triangles[f].vertices[0],
                      triangles[f].vertices[1],
                      triangles[f].vertices[2]}};
          std::sort(t.begin(), t.end());
          const auto first =
            std::lower_bound(faces.begin(), faces.end(), Face{t, 0});
          if (first == faces.end() || first->points != t)
            fail(data.name(data.face_origins[f]) +
                 ", a triangle, is no face of any tetrahedron");
          const bool interior =
            (first + 1 != faces.end() && (first + 1)->points == t);
          if (!interior)
            boundary.emplace_back(t, f);
        }
      std::sort(boundary.begin(), boundary.end());
      std::vector<CellData<2>> kept;
      kept.reserve(boundary.size());
      for (std::size_t i = 0; i < boundary.size(); ++i)
        {
          const auto &face = triangles[boundary[i].second];
          if (i > 0 && boundary[i].first == boundary[i - 1].first)
            {
              const auto &before = triangles[boundary[i - 1].second];
              if (before.boundary_id != face.boundary_id)
                fail(data.name(data.face_origins[boundary[i].second]) +
                     " repeats the boundary triangle of " +
                     data.name(data.face_origins[boundary[i - 1].second]) +
                     " with another id (" + std::to_string(face.boundary_id) +
                     " against " + std::to_string(before.boundary_id) + ")");
              continue;
            }
          kept.push_back(face);
        }
      triangles = std::move(kept);

      GridTools::delete_unused_vertices(data.vertices, data.cells, data.faces);
      const std::vector<unsigned int> old_cell =
        order_for_locality(data.vertices, data.cells, data.faces);
      auto origins = std::make_shared<std::vector<MeshData::Origin>>();
      origins->reserve(old_cell.size());
      for (const unsigned int c : old_cell)
        origins->push_back(data.cell_origins[c]);
      triangulation.clear();
      try
        {
          triangulation.create_triangulation(data.vertices,
                                             data.cells,
                                             data.faces);
        }
      catch (const std::exception &e)
        {
          fail(error_message(e));
        }
      // A copy of the element word: @p data does not outlive the reader.
      MeshData names;
      names.element_word = data.element_word;
      // The origins now live in the namer, in the cells' new order.
      data.cell_origins.clear();
      // A cell index past the mesh (a scene refilled in code after this
      // mesh was read) is named by its index.
      return [names, origins](const unsigned int cell) {
        return cell < origins->size() ? names.name((*origins)[cell]) :
                                        "cell " + std::to_string(cell);
      };
    }
  } // namespace Mesh
} // namespace softface

// VTK XML meshes as other tools write them: the unit cube in six tetrahedra
// written by tests/data/vtu/make_vtu.py (independent of the reader, after the
// VTK specification) as ascii, inline binary + zlib with 64-bit headers,
// appended raw, and appended + zlib, and split into pieces with duplicated
// interface points as a parallel writer saves it (ascii, and appended + zlib
// in several blocks with 32-bit headers, Float32 points and Int32 indices),
// with a vertex and a line cell, an empty piece and a ghost copy of a
// tetrahedron to skip. Each must give 6 tetrahedra of total volume 1 with
// material id 7 on 8 vertices, and boundary ids 3 on the two triangles of
// z = 0 and 4 on the ten others: cell for cell and face for face the mesh of
// the one-piece ascii file.
//
// Then damaged copies of cube6_appended_zlib.vtu, truncated at every length
// and with a hostile 64-bit value written over every position of its appended
// data, must each be read or refused with a softface::Error, never crash: the
// test prints how many were read (the copy without its final newline, and
// those whose damage hit only a header word the reader does not need, the
// full-block size of a single-block array) and how many were refused.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include "tests.h"
#include <softface/core/error.h>
#include <softface/core/mesh.h>
#include <softface/core/tetrahedron.h>
#include <softface/io/mesh_reader.h>
#include <softface/io/vtu_reader.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

using namespace softface;

namespace
{
  // A cell or boundary face as its sorted vertex coordinates and its id, so
  // that two meshes compare whatever their numbering.
  using Shape = std::pair<std::vector<std::array<double, 3>>, unsigned int>;

  template <typename Accessor>
  Shape
  shape_of(const Accessor &object, const unsigned int id)
  {
    Shape shape{{}, id};
    for (const unsigned int v : object->vertex_indices())
      {
        const Point<3> &x = object->vertex(v);
        shape.first.push_back({{x[0], x[1], x[2]}});
      }
    std::sort(shape.first.begin(), shape.first.end());
    return shape;
  }

  struct Shapes
  {
    std::multiset<Shape> cells, faces;
  };

  Shapes
  shapes_of(const Triangulation<3> &tria)
  {
    Shapes shapes;
    for (const auto &cell : tria.active_cell_iterators())
      {
        shapes.cells.insert(shape_of(cell, cell->material_id()));
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            shapes.faces.insert(shape_of(face, face->boundary_id()));
      }
    return shapes;
  }

  unsigned int
  n_found_in(const std::multiset<Shape> &these,
             const std::multiset<Shape> &reference)
  {
    unsigned int n = 0;
    for (const Shape &s : these)
      n += (reference.count(s) == 1);
    return n;
  }

  std::string
  file_bytes(const std::string &filename)
  {
    std::ifstream in(filename, std::ios::binary);
    return {std::istreambuf_iterator<char>(in),
            std::istreambuf_iterator<char>()};
  }
} // namespace

SOFTFACE_TEST(vtu_formats)
{
  Shapes reference;
  for (const std::string name : {"ascii",
                                 "binary_zlib",
                                 "appended_raw",
                                 "appended_zlib",
                                 "pieces_ascii",
                                 "pieces_appended_zlib"})
    {
      Triangulation<3> tria;
      Mesh::read_file(softface_tests::source_file("data/vtu/cube6_" + name +
                                                  ".vtu"),
                      tria);
      Mesh::check_cells(tria, name);
      double                                 volume = 0.;
      std::map<types::material_id, unsigned> n_cells_with;
      std::map<types::boundary_id, unsigned> n_faces_with, n_bottom_faces_with;
      for (const auto &cell : tria.active_cell_iterators())
        {
          volume += Tetrahedron::signed_volume(Tetrahedron::vertices(cell));
          ++n_cells_with[cell->material_id()];
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                ++n_faces_with[face->boundary_id()];
                n_bottom_faces_with[face->boundary_id()] +=
                  (face->center()[2] == 0.);
              }
        }
      deallog << name << ": " << tria.n_active_cells() << " cells, "
              << tria.n_used_vertices() << " vertices, volume " << std::fixed
              << std::setprecision(9) << volume << std::defaultfloat
              << std::endl;
      for (const auto &[id, n] : n_cells_with)
        deallog << name << ": material id " << id << ": " << n << " cells"
                << std::endl;
      for (const auto &[id, n] : n_faces_with)
        deallog << name << ": boundary id " << id << ": " << n << " faces, "
                << n_bottom_faces_with[id] << " of them at z = 0" << std::endl;

      const Shapes shapes = shapes_of(tria);
      if (name == "ascii")
        reference = shapes;
      const unsigned int n_cells = n_found_in(shapes.cells, reference.cells);
      const unsigned int n_faces = n_found_in(shapes.faces, reference.faces);
      deallog << name
              << ": cells and boundary faces as in cube6_ascii: " << n_cells
              << " of " << reference.cells.size() << ", " << n_faces << " of "
              << reference.faces.size() << std::endl;
      AssertThrow(tria.n_active_cells() == 6 && tria.n_used_vertices() == 8 &&
                    std::abs(volume - 1.) < 1e-14 && n_cells_with[7] == 6 &&
                    n_bottom_faces_with[3] == 2 && n_faces_with[3] == 2 &&
                    n_faces_with[4] == 10,
                  ExcMessage(name + " is not the cube in six tetrahedra"));
      AssertThrow(n_cells == 6 && n_faces == 12 && shapes.cells.size() == 6 &&
                    shapes.faces.size() == 12,
                  ExcMessage(name + " differs from cube6_ascii"));
    }

  // A point data array the file does not have: refused with one message
  // that names the array and the file.
  try
    {
      Mesh::read_vtu_point_field(softface_tests::source_file(
                                   "data/vtu/cube6_pieces_ascii.vtu"),
                                 "displacement");
      deallog << "point data 'displacement' of cube6_pieces_ascii: read"
              << std::endl;
    }
  catch (const Error &e)
    {
      const std::string message = e.what();
      deallog << "point data 'displacement' of cube6_pieces_ascii refused, "
                 "the message naming the array and the file: "
              << (message.find("'displacement'") != std::string::npos &&
                  message.find("cube6_pieces_ascii.vtu'") != std::string::npos)
              << std::endl;
    }

  // Damaged copies: read or refused, nothing else.
  const std::string original =
    file_bytes(softface_tests::source_file("data/vtu/cube6_appended_zlib.vtu"));
  const std::string damaged = "vtu_formats_damaged.vtu";
  unsigned int      n_read = 0, n_refused = 0;
  const auto        attempt = [&](const std::string &bytes) {
    std::ofstream(damaged, std::ios::binary) << bytes;
    Triangulation<3> tria;
    try
      {
        Mesh::read_vtu(damaged, tria);
        ++n_read;
      }
    catch (const Error &)
      {
        ++n_refused;
      }
  };
  for (std::size_t size = 0; size < original.size(); ++size)
    attempt(original.substr(0, size));
  deallog << "cube6_appended_zlib truncated to each of its " << original.size()
          << " lengths: " << n_read << " read, " << n_refused << " refused"
          << std::endl;

  n_read = n_refused      = 0;
  const std::size_t begin = original.find('_', original.find("<AppendedData"));
  const std::size_t end   = original.rfind("\n</AppendedData>");
  for (const std::uint64_t hostile :
       {~std::uint64_t(0), std::uint64_t(1) << 32})
    for (std::size_t p = begin + 1; p + 8 <= end; ++p)
      {
        std::string bytes = original;
        std::memcpy(&bytes[p], &hostile, 8);
        attempt(bytes);
      }
  deallog << "cube6_appended_zlib with 2^64-1 or 2^32 over each of its "
          << end - begin - 8 << " appended positions: " << n_read << " read, "
          << n_refused << " refused" << std::endl;
}

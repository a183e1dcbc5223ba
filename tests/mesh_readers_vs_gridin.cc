// softface's own mesh readers (gmsh 2.2 and 4.1, legacy VTK)
// against deal.II's GridIn on valid files: the same cells on the same
// points, the same material ids, the same boundary ids on every boundary
// face. (Files the checks refuse are in tests/bad_input and the fuzzer.)

#include <deal.II/grid/grid_in.h>

#include <softface/io/mesh_reader.h>

#include "tests.h"

#include <fstream>
#include <map>
#include <sstream>

using namespace softface;

namespace
{
  using Key = std::array<long long, 3>;

  Key
  key_of(const Point<3> &x)
  {
    return {{std::llround(x[0] * 1e6),
             std::llround(x[1] * 1e6),
             std::llround(x[2] * 1e6)}};
  }

  // Material id per cell and boundary id per boundary face, keyed by the
  // sorted positions of their vertices (independent of any numbering).
  struct Ids
  {
    std::map<std::vector<Key>, unsigned int> cells, faces;
  };

  Ids
  ids_of(const Triangulation<3> &tria)
  {
    Ids ids;
    for (const auto &cell : tria.active_cell_iterators())
      {
        std::vector<Key> k;
        for (const unsigned int v : cell->vertex_indices())
          k.push_back(key_of(cell->vertex(v)));
        std::sort(k.begin(), k.end());
        ids.cells[k] = cell->material_id();
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              std::vector<Key> f;
              for (const unsigned int v : face->vertex_indices())
                f.push_back(key_of(face->vertex(v)));
              std::sort(f.begin(), f.end());
              ids.faces[f] = face->boundary_id();
            }
      }
    return ids;
  }

  unsigned int
  differences(const std::map<std::vector<Key>, unsigned int> &a,
              const std::map<std::vector<Key>, unsigned int> &b)
  {
    unsigned int n =
      (a.size() > b.size()) ? a.size() - b.size() : b.size() - a.size();
    for (const auto &[k, id] : a)
      {
        const auto other = b.find(k);
        if (other != b.end() && other->second != id)
          ++n;
        else if (other == b.end())
          ++n;
      }
    return n;
  }
} // namespace

SOFTFACE_TEST(mesh_readers_vs_gridin)
{
  const std::string data = SOFTFACE_TESTS_SOURCE_DIR "/data/";
  // The VTK seed with point data (and a field) before its cell data: the
  // material ids must still be found.
  {
    std::ifstream     in(data + "mesh_seeds/box.vtk");
    std::stringstream text;
    text << in.rdbuf();
    std::string       vtk  = text.str();
    const std::size_t cell = vtk.find("CELL_DATA");
    std::string       point_data =
      "POINT_DATA 148\nSCALARS temperature double 1\nLOOKUP_TABLE default\n";
    for (unsigned int i = 0; i < 148; ++i)
      point_data += std::to_string(i % 7) + (i % 10 == 9 ? "\n" : " ");
    point_data += "\nVECTORS velocity float\n";
    for (unsigned int i = 0; i < 148; ++i)
      point_data += "0 1 2\n";
    std::ofstream("box_point_data_first.vtk")
      << vtk.substr(0, cell) << point_data << vtk.substr(cell);
  }
  for (const std::string file : {"mesh_seeds/box41.msh",
                                 "mesh_seeds/box22.msh",
                                 "mesh_seeds/box.vtk",
                                 "box_point_data_first.vtk",
                                 "offcentre_coarse/mesh.msh"})
    {
      const std::string path =
        (file.find('/') == std::string::npos ? "" : data) + file;
      Triangulation<3> by_gridin, by_softface;
      {
        GridIn<3>     grid_in(by_gridin);
        std::ifstream in(path);
        if (file.substr(file.size() - 3) == "vtk")
          grid_in.read_vtk(in);
        else
          grid_in.read_msh(in);
      }
      Mesh::read_file(path, by_softface);
      const Ids a = ids_of(by_gridin), b = ids_of(by_softface);

      deallog << file << ": " << by_softface.n_active_cells() << " tetrahedra, "
              << by_softface.n_used_vertices() << " points, " << b.faces.size()
              << " boundary faces" << std::endl;
      softface_tests::check_equal(file + ": tetrahedra (GridIn: the same)",
                                  by_gridin.n_active_cells(),
                                  by_softface.n_active_cells());
      softface_tests::check_equal(file + ": points (GridIn: the same)",
                                  by_gridin.n_used_vertices(),
                                  by_softface.n_used_vertices());
      softface_tests::check_equal(file + ": cells or material ids that differ",
                                  differences(a.cells, b.cells),
                                  0);
      softface_tests::check_equal(file + ": boundary faces or ids that differ",
                                  differences(a.faces, b.faces),
                                  0);
      std::map<unsigned int, unsigned int> per_id;
      for (const auto &[k, id] : b.faces)
        ++per_id[id];
      for (const auto &[id, n] : per_id)
        deallog << file << ": boundary id " << id << " on " << n << " faces"
                << std::endl;
    }
}

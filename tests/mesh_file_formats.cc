// Mesh files: the generated cube written by deal.II's GridOut as legacy VTK
// (and turned here into legacy VTK 5.1's OFFSETS / CONNECTIVITY layout),
// gmsh .msh and serialised .vtu, and read back by Mesh::read_file, keeps its
// cells, vertices, material ids and boundary ids, and gives the same linear
// FEM answer as the cube it came from. (gmsh 4.1 files from gmsh itself are
// read in peer_calculix_cube30k.)

#include <deal.II/grid/grid_out.h>

#include <softface/io/mesh_reader.h>
#include <softface/models/linear_fem.h>

#include "scenes.h"
#include "tests.h"

#include <fstream>
#include <sstream>

using namespace softface;

namespace
{
  Vector<double>
  lift(const Scene &scene)
  {
    Models::LinearFEM model;
    model.set_solver("direct", 0.);
    model.setup(scene);
    Vector<double> u;
    model.solve(softface_tests::move_bone(scene, Point<3>(0, 0, 6)), u);
    return u;
  }

  // Displacement per vertex position, to compare across vertex numberings.
  std::map<std::array<long long, 3>, Tensor<1, 3>>
  by_position(const Scene &scene, const Vector<double> &u)
  {
    std::map<std::array<long long, 3>, Tensor<1, 3>> result;
    const auto &vertices = scene.triangulation.get_vertices();
    for (unsigned int v = 0; v < vertices.size(); ++v)
      if (scene.vertex_dofs()[v][0] != numbers::invalid_dof_index)
        {
          Tensor<1, 3> d;
          for (unsigned int c = 0; c < 3; ++c)
            d[c] = u[scene.vertex_dofs()[v][c]];
          result[{{std::llround(vertices[v][0] * 1e6),
                   std::llround(vertices[v][1] * 1e6),
                   std::llround(vertices[v][2] * 1e6)}}] = d;
        }
    return result;
  }

  // GridOut's legacy VTK (version 3.0: "CELLS n size", then per cell its
  // point count and points) in the layout of version 5.1: "CELLS n+1 m",
  // OFFSETS and CONNECTIVITY.
  void
  write_vtk_5(const std::string &version_3, std::ostream &out)
  {
    std::istringstream in(version_3);
    std::string        line;
    std::getline(in, line);
    out << "# vtk DataFile Version 5.1\n";
    while (std::getline(in, line))
      {
        if (line.rfind("CELLS ", 0) != 0)
          {
            out << line << '\n';
            continue;
          }
        std::istringstream header(line.substr(6));
        unsigned int       n_cells = 0;
        header >> n_cells;
        std::vector<unsigned int> offsets = {0}, connectivity;
        for (unsigned int c = 0; c < n_cells; ++c)
          {
            unsigned int k = 0;
            in >> k;
            for (unsigned int v = 0; v < k; ++v)
              {
                unsigned int point = 0;
                in >> point;
                connectivity.push_back(point);
              }
            offsets.push_back(connectivity.size());
          }
        std::getline(in, line); // the rest of the last cell's line
        out << "CELLS " << offsets.size() << ' ' << connectivity.size()
            << "\nOFFSETS vtktypeint64\n";
        for (const unsigned int o : offsets)
          out << o << '\n';
        out << "CONNECTIVITY vtktypeint64\n";
        for (const unsigned int v : connectivity)
          out << v << '\n';
      }
  }
} // namespace

SOFTFACE_TEST(mesh_file_formats)
{
  // 5 mm grid boxes: every coordinate is a multiple of 5, which GridOut's
  // six-digit ASCII output writes exactly.
  Scene original;
  softface_tests::make_cube_scene(original, 6 * 16 * 16 * 16);
  const auto reference = by_position(original, lift(original));

  GridOut           grid_out;
  GridOutFlags::Vtk vtk_flags;
  vtk_flags.output_cells = true;
  vtk_flags.output_faces = true;
  vtk_flags.output_edges = false;
  grid_out.set_flags(vtk_flags);
  GridOutFlags::Vtu vtu_flags;
  vtu_flags.serialize_triangulation = true;
  grid_out.set_flags(vtu_flags);
  GridOutFlags::Msh msh_flags(/*write_faces=*/true);
  grid_out.set_flags(msh_flags);

  for (const std::string format : {"vtk", "vtk 5.1", "msh", "vtu"})
    {
      const std::string extension = format.substr(0, 3);
      const std::string filename =
        "mesh_file_formats_cube" +
        std::string(format == "vtk 5.1" ? "_5" : "") + "." + extension;
      {
        std::ofstream out(filename);
        if (format == "vtk 5.1")
          {
            std::ostringstream version_3;
            grid_out.write_vtk(original.triangulation, version_3);
            write_vtk_5(version_3.str(), out);
          }
        else if (extension == "vtk")
          grid_out.write_vtk(original.triangulation, out);
        else if (extension == "msh")
          grid_out.write_msh(original.triangulation, out);
        else
          grid_out.write_vtu(original.triangulation, out);
      }
      Scene scene;
      Mesh::read_file(filename, scene.triangulation);
      scene.mesh_description = filename;
      scene.segments         = original.segments;
      scene.setup();

      softface_tests::check_equal(format + ": cells",
                                  scene.triangulation.n_active_cells(),
                                  original.triangulation.n_active_cells());
      softface_tests::check_equal(format + ": vertices",
                                  scene.n_vertices(),
                                  original.n_vertices());
      softface_tests::check_equal(format + ": join points of 'fixed'",
                                  scene.n_join_vertices(0),
                                  original.n_join_vertices(0));
      softface_tests::check_equal(format + ": join points of 'bone'",
                                  scene.n_join_vertices(1),
                                  original.n_join_vertices(1));

      const auto   u         = by_position(scene, lift(scene));
      double       max       = 0.;
      unsigned int unmatched = 0;
      for (const auto &[key, d] : u)
        {
          const auto r = reference.find(key);
          if (r == reference.end())
            ++unmatched;
          else
            max = std::max(max, (d - r->second).norm());
        }
      softface_tests::check_equal(format +
                                    ": vertices not at an original vertex",
                                  unmatched + (reference.size() - u.size()),
                                  0);
      softface_tests::check_below(format + ": max |u - u_original| (mm)",
                                  max,
                                  1e-12);
    }
}

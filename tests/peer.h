#ifndef softface_tests_peer_h
#define softface_tests_peer_h

// Reading a peer's nodal displacements (tests/data/cube30k,
// tests/data/offcentre_coarse) onto a scene.

#include <deal.II/base/utilities.h>

#include <softface/core/planning.h>
#include <softface/core/scene.h>
#include <softface/simulator/simulator.h>

#include "tests.h"

#include <fstream>
#include <map>

namespace softface_tests
{
  using namespace softface;


  // Vertices binned on a 1 mm grid; a point is matched to the nearest vertex
  // in its own and the neighbouring bins (the CSV rounds coordinates to 12
  // significant digits, so exact keys could fall on either side of a bin).
  using Bin = std::array<long long, 3>;

  inline Bin
  bin_of(const Point<3> &x)
  {
    return {{static_cast<long long>(std::floor(x[0])),
             static_cast<long long>(std::floor(x[1])),
             static_cast<long long>(std::floor(x[2]))}};
  }

  // The peer's CSV as a vector on the scene's DoF layout.
  inline Vector<double>
  read_peer(const Scene &scene, const std::string &filename)
  {
    std::map<Bin, std::vector<unsigned int>> vertices_in;
    const auto &vertices = scene.triangulation.get_vertices();
    for (unsigned int v = 0; v < vertices.size(); ++v)
      if (scene.vertex_dofs()[v][0] != numbers::invalid_dof_index)
        vertices_in[bin_of(vertices[v])].push_back(v);
    const auto nearest = [&](const Point<3> &x) {
      unsigned int best = numbers::invalid_unsigned_int;
      const Bin    b    = bin_of(x);
      for (long long i = -1; i <= 1; ++i)
        for (long long j = -1; j <= 1; ++j)
          for (long long k = -1; k <= 1; ++k)
            {
              const auto bin =
                vertices_in.find({{b[0] + i, b[1] + j, b[2] + k}});
              if (bin != vertices_in.end())
                for (const unsigned int v : bin->second)
                  if (best == numbers::invalid_unsigned_int ||
                      x.distance(vertices[v]) < x.distance(vertices[best]))
                    best = v;
            }
      AssertThrow(best != numbers::invalid_unsigned_int &&
                    x.distance(vertices[best]) < 1e-6,
                  ExcMessage("peer vertex not in the mesh"));
      return best;
    };

    Vector<double> u(scene.dof_handler.n_dofs());
    std::ifstream  in(filename);
    AssertThrow(in, ExcMessage("cannot open " + filename));
    std::string  line;
    unsigned int n_matched = 0;
    std::getline(in, line); // header
    while (std::getline(in, line))
      {
        const auto values =
          Utilities::string_to_double(Utilities::split_string_list(line));
        const unsigned int v =
          nearest(Point<3>(values[0], values[1], values[2]));
        for (unsigned int c = 0; c < 3; ++c)
          u[scene.vertex_dofs()[v][c]] = values[3 + c];
        ++n_matched;
      }
    AssertThrow(n_matched == scene.n_vertices(),
                ExcMessage("the peer file does not cover every vertex"));
    return u;
  }
  /// The scene and planning of the parameter file @p name in tests/,
  /// through the whole parameter path.
  inline Planning
  read_scene(const std::string &name, ParameterHandler &prm, Scene &scene)
  {
    Simulator::read_parameters(source_file(name), prm);
    scene.parse_parameters(prm, source_file(""));
    Planning planning;
    planning.parse_parameters(prm, scene);
    return planning;
  }

  /// The shared gmsh cube scene and its planning from
  /// peer_calculix_cube30k.prm.
  inline Vector<double>
  read_peer_scene(ParameterHandler &prm, Scene &scene)
  {
    return read_scene("peer_calculix_cube30k.prm", prm, scene)
      .prescribed_displacement(scene);
  }

  /// CalculiX's linear or NLGEOM nodal displacements on that scene.
  inline Vector<double>
  calculix_displacements(const Scene &scene, const std::string &analysis)
  {
    return read_peer(scene,
                     source_file("data/cube30k/calculix_" + analysis +
                                 "_displacements.csv"));
  }
} // namespace softface_tests

#endif

// Volume/surface mapping (seed 3.4): the shape-function mapping reproduces an
// affine displacement field exactly, at skin points inside the mesh and at
// points off it that it projects onto the mesh's skin (P1 shape functions
// extrapolate an affine field exactly); inverse distance weighting reproduces
// a constant field exactly, and between two known points 1 and 3 mm away
// gives the value of seed eq. 14 computed here (weights 1/d, not d: 0.25,
// not 0.75); a skin out of the mesh's reach is refused.

#include <softface/core/error.h>
#include <softface/core/mesh.h>
#include <softface/mapping/skin_mapping.h>

#include "scenes.h"
#include "surfaces.h"
#include "tests.h"

using namespace softface;

namespace
{
  double
  max_error(const std::vector<Tensor<1, 3>>                     &u,
            const std::vector<Point<3>>                         &points,
            const std::function<Tensor<1, 3>(const Point<3> &)> &exact)
  {
    double error = 0.;
    for (unsigned int i = 0; i < u.size(); ++i)
      error = std::max(error, (u[i] - exact(points[i])).norm());
    return error;
  }
} // namespace

SOFTFACE_TEST(mapping_skin)
{
  // An 80 mm cube of tissue (distorted inside, flat outer faces).
  Scene scene;
  softface_tests::make_distorted_cube_scene(scene, 3000, true);
  const auto mesh =
    SurfaceMapping::VolumeMesh::from_triangulation(scene.triangulation,
                                                   {Mesh::cube_outer_face});
  deallog << "mesh: " << mesh.cells.size() << " tetrahedra, "
          << mesh.skin.triangles.size() << " skin triangles" << std::endl;

  Tensor<2, 3> A;
  A[0][0] = 0.01, A[0][1] = -0.02, A[0][2] = 0.005;
  A[1][0] = 0.015, A[1][1] = 0.03, A[1][2] = -0.01;
  A[2][0] = -0.004, A[2][1] = 0.02, A[2][2] = -0.025;
  const Tensor<1, 3> b      = Point<3>(0.5, -1., 2.);
  const auto         affine = [&](const Point<3> &x) -> Tensor<1, 3> {
    return A * x + b;
  };
  std::vector<Tensor<1, 3>> vertex_u(mesh.vertices.size());
  for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
    vertex_u[v] = affine(mesh.vertices[v]);

  // A sphere inside the mesh, and a box 1 mm outside its outer faces
  // (an icosphere projected onto the box).
  const auto sphere =
    softface_tests::transformed(softface_tests::unit_icosphere(4),
                                [](const Point<3> &p) {
                                  return Point<3>(40, 40, 40) + 30. * p;
                                });
  const auto box = softface_tests::transformed(
    softface_tests::unit_icosphere(5), [](const Point<3> &p) {
      const double m =
        std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
      return Point<3>(40, 40, 40) + 41. / m * p;
    });
  deallog << "skins: sphere " << sphere.points.size() << " points, box "
          << box.points.size() << " points" << std::endl;

  SurfaceMapping::Parameters parameters;
  std::vector<Tensor<1, 3>>  u;
  for (const auto &[name, skin] :
       std::vector<std::pair<std::string, const SurfaceMapping::Surface *>>{
         {"sphere inside", &sphere}, {"box outside", &box}})
    {
      const auto mapping =
        SurfaceMapping::shape_function_mapping(mesh, *skin, parameters);
      mapping.map(vertex_u, u);
      softface_tests::check_equal(name + ": points inside a tetrahedron",
                                  mapping.n_inside,
                                  name == "sphere inside" ?
                                    skin->points.size() :
                                    0);
      softface_tests::check_equal(name + ": points out of reach",
                                  mapping.n_outside,
                                  0);
      softface_tests::check_below(name +
                                    ": shape functions, max |u - u_affine| mm",
                                  max_error(u, skin->points, affine),
                                  1e-10);
    }

  // Inverse distance weighting: a constant field everywhere it reaches.
  const Tensor<1, 3> c = Point<3>(0.3, -1.2, 2.5);
  std::fill(vertex_u.begin(), vertex_u.end(), c);
  for (const auto &[radius, rings] :
       std::vector<std::pair<double, unsigned int>>{{3., 5}, {12., 12}})
    {
      parameters.radius = radius;
      parameters.rings  = rings;
      const auto mapping =
        SurfaceMapping::inverse_distance_mapping(mesh, box, parameters);
      mapping.map(vertex_u, u);
      double error = 0.;
      for (unsigned int i = 0; i < u.size(); ++i)
        if (mapping.row_start[i + 1] > mapping.row_start[i])
          error = std::max(error, (u[i] - c).norm());
      const std::string name = "inverse distance, " +
                               softface_tests::rounded(radius) + " mm, " +
                               std::to_string(rings) + " rings";
      softface_tests::check_equal(name + ": points out of reach",
                                  mapping.n_outside,
                                  0);
      deallog << name << ": points without a known point in range: "
              << mapping.n_without_neighbours << std::endl;
      softface_tests::check_below(name + ": max |u - c| mm", error, 1e-12);
    }
  softface_tests::check_equal(
    "12 mm, 12 rings: points without a known point (again)",
    SurfaceMapping::inverse_distance_mapping(mesh, box, parameters)
      .n_without_neighbours,
    0);

  // Inverse distance weighting where the weights matter: a mesh skin
  // triangle A B C whose vertices A and B are skin points p0 and p2 (the
  // known points; C is farther than the reach from every skin point), and a
  // skin point p1 on AB 1 mm from A and 3 mm from B. With u(A) = 0 and
  // u(B) = 1, seed eq. 14 gives u(p1) = (0 / 1 + 1 / 3) / (1 / 1 + 1 / 3).
  {
    SurfaceMapping::VolumeMesh strip;
    strip.vertices = {Point<3>(0, 0, 0),
                      Point<3>(4, 0, 0),
                      Point<3>(2, 20, 0),
                      Point<3>(2, 5, -20)};
    strip.cells    = {{{0, 1, 2, 3}}};
    strip.skin     = {strip.vertices, {{{0, 1, 2}}}};
    SurfaceMapping::Surface skin;
    skin.points    = {Point<3>(0, 0, 0),
                      Point<3>(1, 0, 0),
                      Point<3>(4, 0, 0),
                      Point<3>(2, 0.5, 0)};
    skin.triangles = {{{0, 1, 3}}, {{1, 2, 3}}};
    SurfaceMapping::Parameters idw;
    idw.method = SurfaceMapping::Method::inverse_distance;
    idw.radius = 3.5;
    const auto mapping =
      SurfaceMapping::inverse_distance_mapping(strip, skin, idw);
    std::vector<Tensor<1, 3>> strip_u(4);
    strip_u[1][0] = 1.;
    strip_u[2][0] = 5.; // C is no known point: it must not count
    mapping.map(strip_u, u);
    const double exact = (0. / 1. + 1. / 3.) / (1. / 1. + 1. / 3.);
    softface_tests::print("inverse distance, p1 between A (1 mm) and B (3 mm): "
                          "u(p1)",
                          u[1][0],
                          6);
    softface_tests::check_below(
      "inverse distance, |u(p1) - (0/1 + 1/3) / (1/1 + 1/3)|",
      std::abs(u[1][0] - exact),
      1e-12);
  }

  // A skin far from the mesh (another frame) is refused.
  const auto far = softface_tests::transformed(sphere, [](const Point<3> &p) {
    return p + Point<3>(500, 0, 0);
  });
  for (const auto method : {SurfaceMapping::Method::shape_functions,
                            SurfaceMapping::Method::inverse_distance})
    try
      {
        parameters.method = method;
        SurfaceMapping::initialise(mesh, far, parameters);
        deallog << "far skin accepted (wrong)" << std::endl;
      }
    catch (const Error &e)
      {
        deallog << SurfaceMapping::name_of(method) << ": " << e.what()
                << std::endl;
      }
}

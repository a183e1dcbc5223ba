// Volume/surface mapping (Mollemans et al. 2007, Sec. 3.4): the shape-function
// mapping reproduces an affine displacement field exactly, at skin points
// inside the mesh and at points off it that it projects onto the mesh's skin
// (P1 shape functions extrapolate an affine field exactly); for a field that is
// not affine, where another tetrahedron than the right one gives another value,
// it gives the P1 interpolant of the containing tetrahedron (inside) and of the
// tetrahedron of the skin face a point projects onto (outside), both found
// here by brute force with barycentric coordinates computed here; inverse
// distance weighting reproduces a constant field exactly, between two known
// points 1 and 3 mm away gives the value of the paper's eq. 14 computed here
// (weights 1/d, not d: 0.25, not 0.75), and counts rings as the paper does
// (a known point two edges away counts from 3 rings on); a skin out of the
// mesh's reach is refused.

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

  // The barycentric coordinates of p in tetrahedron x (solved here, not by
  // the code under test).
  std::array<double, 4>
  barycentric(const std::array<Point<3>, 4> &x, const Point<3> &p)
  {
    Tensor<2, 3> J;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int k = 0; k < 3; ++k)
        J[i][k] = x[k + 1][i] - x[0][i];
    const Tensor<1, 3> xi = invert(J) * (p - x[0]);
    return {{1. - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]}};
  }

  // One tetrahedron whose skin is the triangle A = (0, 0, 0), B = (b, 0, 0)
  // and C, C far from A and B.
  SurfaceMapping::VolumeMesh
  one_tetrahedron(const double b)
  {
    SurfaceMapping::VolumeMesh mesh;
    mesh.vertices = {Point<3>(0, 0, 0),
                     Point<3>(b, 0, 0),
                     Point<3>(2, 20, 0),
                     Point<3>(2, 5, -20)};
    mesh.cells    = {{{0, 1, 2, 3}}};
    mesh.skin     = {mesh.vertices, {{{0, 1, 2}}}};
    return mesh;
  }

  // Not affine: its P1 interpolant changes from one tetrahedron to the next.
  Tensor<1, 3>
  curved(const Point<3> &x)
  {
    Tensor<1, 3> u;
    u[0] = x[1] * x[2] / 800.;
    u[1] = x[0] * x[0] / 400. - x[2] / 20.;
    u[2] = 3. * std::sin(x[0] / 7.) * std::cos(x[1] / 9.);
    return u;
  }

  Tensor<1, 3>
  interpolant(const SurfaceMapping::VolumeMesh &mesh,
              const unsigned int                c,
              const Point<3>                   &p)
  {
    std::array<Point<3>, 4> x;
    for (unsigned int v = 0; v < 4; ++v)
      x[v] = mesh.vertices[mesh.cells[c][v]];
    const auto   lambda = barycentric(x, p);
    Tensor<1, 3> u;
    for (unsigned int v = 0; v < 4; ++v)
      u += lambda[v] * curved(x[v]);
    return u;
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
                                  1e-13);
    }

  // A field that is not affine. Inside: the interpolant of a tetrahedron
  // that contains the point (on a shared face any of them gives the same
  // value). Outside (the box points with one coordinate off the cube, whose
  // orthogonal projection onto that face lies strictly inside one skin
  // triangle): the interpolant of that triangle's tetrahedron, extrapolated.
  for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
    vertex_u[v] = curved(mesh.vertices[v]);
  {
    const auto mapping =
      SurfaceMapping::shape_function_mapping(mesh, sphere, parameters);
    mapping.map(vertex_u, u);
    double       error = 0., spread = 0.;
    unsigned int found = 0;
    for (unsigned int i = 0; i < sphere.points.size(); ++i)
      {
        const Point<3> &p = sphere.points[i];
        for (unsigned int c = 0; c < mesh.cells.size(); ++c)
          {
            std::array<Point<3>, 4> x;
            for (unsigned int v = 0; v < 4; ++v)
              x[v] = mesh.vertices[mesh.cells[c][v]];
            const auto lambda = barycentric(x, p);
            if (*std::min_element(lambda.begin(), lambda.end()) >= -1e-12)
              {
                error =
                  std::max(error, (u[i] - interpolant(mesh, c, p)).norm());
                ++found;
                break;
              }
          }
        spread = std::max(spread, (u[i] - curved(p)).norm());
      }
    softface_tests::check_equal("curved field, sphere: points in a tetrahedron "
                                "found by brute force",
                                found,
                                sphere.points.size());
    softface_tests::print("curved field, sphere: max |u - field| mm "
                          "(interpolation error)",
                          spread,
                          2);
    softface_tests::check_below("curved field, sphere: max |u - its "
                                "tetrahedron's interpolant| mm",
                                error,
                                1e-12);
  }
  {
    const auto mapping =
      SurfaceMapping::shape_function_mapping(mesh, box, parameters);
    mapping.map(vertex_u, u);
    double       error = 0.;
    unsigned int found = 0;
    for (unsigned int i = 0; i < box.points.size(); ++i)
      {
        const Point<3> &p     = box.points[i];
        Point<3>        q     = p;
        unsigned int    n_off = 0;
        for (unsigned int d = 0; d < 3; ++d)
          if (p[d] < 0. || p[d] > 80.)
            {
              q[d] = p[d] < 0. ? 0. : 80.;
              ++n_off;
            }
        if (n_off != 1)
          continue;
        for (unsigned int t = 0; t < mesh.skin.triangles.size(); ++t)
          {
            const auto     &tri  = mesh.skin.triangles[t];
            const Point<3> &a    = mesh.vertices[tri[0]],
                           &b    = mesh.vertices[tri[1]],
                           &c    = mesh.vertices[tri[2]];
            const Tensor<1, 3> n = cross_product_3d(b - a, c - a);
            if (std::abs(n * (q - a)) > 1e-9 * n.norm())
              continue;
            const double area = n.norm();
            const double wa =
              cross_product_3d(b - q, c - q) * n / (area * area);
            const double wb =
              cross_product_3d(c - q, a - q) * n / (area * area);
            if (std::min({wa, wb, 1. - wa - wb}) > 1e-6)
              {
                error =
                  std::max(error,
                           (u[i] -
                            interpolant(mesh, mesh.cell_of_skin_triangle[t], p))
                             .norm());
                ++found;
                break;
              }
          }
      }
    deallog << "curved field, box: points projecting strictly inside one skin "
               "triangle: "
            << found << std::endl;
    softface_tests::check_below("curved field, box: max |u - its skin "
                                "face's tetrahedron's interpolant| mm",
                                error,
                                1e-12);
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
  // u(B) = 1, the paper's eq. 14 gives
  // u(p1) = (0 / 1 + 1 / 3) / (1 / 1 + 1 / 3).
  {
    const auto              strip = one_tetrahedron(4.);
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

  // Rings: skin points on a line, p0 (known, on A), p1, p2, p3 (known, on
  // B) 1 mm apart, each segment closing a triangle with a point q beside
  // it. p3 is two edges from p1: it counts with 3 rings, not with 2 ("fewer
  // than y rings away", paper, Sec. 3.4), and with 1 ring nothing does.
  // u(A) = 0, u(B) = 1: u(p1) = 0 with 2 rings, (0/1 + 1/2) / (1/1 + 1/2)
  // with 3.
  {
    const auto              strip = one_tetrahedron(3.);
    SurfaceMapping::Surface skin;
    skin.points    = {Point<3>(0, 0, 0),
                      Point<3>(1, 0, 0),
                      Point<3>(2, 0, 0),
                      Point<3>(3, 0, 0),
                      Point<3>(0.5, 0.5, 0),
                      Point<3>(1.5, 0.5, 0),
                      Point<3>(2.5, 0.5, 0)};
    skin.triangles = {{{0, 1, 4}}, {{1, 2, 5}}, {{2, 3, 6}}};
    std::vector<Tensor<1, 3>> strip_u(4);
    strip_u[1][0] = 1.;
    strip_u[2][0] = 5.; // C is no known point: it must not count
    SurfaceMapping::Parameters idw;
    idw.method = SurfaceMapping::Method::inverse_distance;
    idw.radius = 3.5;
    for (const unsigned int rings : {1u, 2u, 3u})
      {
        idw.rings = rings;
        const auto mapping =
          SurfaceMapping::inverse_distance_mapping(strip, skin, idw);
        mapping.map(strip_u, u);
        const double exact =
          rings == 3 ? (0. / 1. + 1. / 2.) / (1. / 1. + 1. / 2.) : 0.;
        const unsigned int n_weights =
          mapping.row_start[2] - mapping.row_start[1];
        softface_tests::check_equal("inverse distance, " +
                                      std::to_string(rings) +
                                      " rings: known points weighted at p1",
                                    n_weights,
                                    rings == 1 ? 0 :
                                    rings == 2 ? 1 :
                                                 2);
        softface_tests::check_below("inverse distance, " +
                                      std::to_string(rings) +
                                      " rings: |u(p1) - exact|",
                                    std::abs(u[1][0] - exact),
                                    1e-12);
      }
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

// Separated lips: a block of tissue (80 mm) cut by a slit in its mid-plane
// z = 40 from the face x = 0 to x = 50, where the two "lips" join. The jaw
// (the top face) closes by 3 mm against the fixed base, pressing the lips
// together (at 8 mm the mass spring model turns 600 tetrahedra inside out,
// with or without the slit: disadvantage 1 of Mollemans et al. 2007, Sec. 2.2,
// not the lips'). Checked cell by cell: no tetrahedron above the slit overlaps
// one below it after the motion (separating axes; cells that share a vertex are
// neighbours, not checked), in every model; the vertex pairs never pass
// through each other. Without the contact (the slit alone), the upper lip
// sinks into the lower one: the check would fail. Then the jaw tilts, so
// that the mouth opens in front and the lips press at the back: the FEM
// models' active set must end with some pairs apart and some in contact.
// There the lips also slide a little along each other, and the pairs,
// node to node, let faces between them cross by about 1e-5 of a cell: that
// is measured, and bounded, not zero.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/planning.h>
#include <softface/models/linear_fem.h>
#include <softface/models/mass_spring.h>
#include <softface/models/mass_tensor.h>
#include <softface/models/nonlinear_fem.h>

#include "effects.h"
#include "tests.h"

using namespace softface;

namespace
{
  using Tet = std::array<Point<3>, 4>;

  // How deep two tetrahedra overlap: the smallest overlap of their
  // projections over the separating axes (face normals, edge crosses);
  // 0 if some axis separates them.
  double
  overlap_depth(const Tet &p, const Tet &q)
  {
    std::vector<Tensor<1, 3>> axes;
    const unsigned int        edges[6][2] = {
             {0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    for (const Tet *t : {&p, &q})
      for (unsigned int f = 0; f < 4; ++f)
        {
          const Point<3> &a = (*t)[(f + 1) % 4], &b = (*t)[(f + 2) % 4],
                         &c = (*t)[(f + 3) % 4];
          axes.push_back(cross_product_3d(b - a, c - a));
        }
    for (const auto &e : edges)
      for (const auto &g : edges)
        axes.push_back(cross_product_3d(p[e[1]] - p[e[0]], q[g[1]] - q[g[0]]));
    double depth = std::numeric_limits<double>::max();
    for (Tensor<1, 3> axis : axes)
      {
        const double norm = axis.norm();
        if (norm < 1e-12)
          continue;
        axis /= norm;
        double p0 = 1e300, p1 = -1e300, q0 = 1e300, q1 = -1e300;
        for (unsigned int v = 0; v < 4; ++v)
          {
            p0 = std::min(p0, axis * p[v]), p1 = std::max(p1, axis * p[v]);
            q0 = std::min(q0, axis * q[v]), q1 = std::max(q1, axis * q[v]);
          }
        depth = std::min(depth, std::min(p1, q1) - std::max(p0, q0));
        if (depth <= 0.)
          return 0.;
      }
    return depth;
  }

  struct Check
  {
    double       depth        = 0.;
    unsigned int overlapping  = 0; // pairs deeper than 1e-6 mm
    double       smallest_gap = 0.;
  };

  // Every cell above the slit against every cell below it that touches a
  // slit vertex and shares no vertex with it, in the deformed mesh.
  Check
  check(const Scene &scene, const Vector<double> &u)
  {
    std::set<unsigned int> above_vertices, below_vertices;
    Check                  result;
    result.smallest_gap = std::numeric_limits<double>::max();
    for (const auto &c : scene.effects.vertex_constraints)
      {
        above_vertices.insert(c.vertex);
        below_vertices.insert(c.partner);
        double gap = 0.;
        for (unsigned int i = 0; i < 3; ++i)
          gap += c.normal[i] * (u[scene.vertex_dofs()[c.vertex][i]] -
                                u[scene.vertex_dofs()[c.partner][i]]);
        result.smallest_gap = std::min(result.smallest_gap, gap);
      }
    std::vector<std::pair<Tet, std::array<unsigned int, 4>>> above, below;
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      {
        Tet                         x;
        std::array<unsigned int, 4> ids;
        bool                        up = false, down = false;
        for (unsigned int a = 0; a < 4; ++a)
          {
            ids[a] = cell->vertex_index(a);
            x[a]   = cell->vertex(a);
            for (unsigned int i = 0; i < 3; ++i)
              x[a][i] += u[scene.vertex_dofs()[ids[a]][i]];
            up |= above_vertices.count(ids[a]) > 0;
            down |= below_vertices.count(ids[a]) > 0;
          }
        if (up)
          above.emplace_back(x, ids);
        if (down)
          below.emplace_back(x, ids);
      }
    for (const auto &[p, p_ids] : above)
      for (const auto &[q, q_ids] : below)
        {
          bool shared = false;
          for (const unsigned int a : p_ids)
            shared |= std::find(q_ids.begin(), q_ids.end(), a) != q_ids.end();
          if (shared)
            continue;
          const double depth = overlap_depth(p, q);
          result.depth       = std::max(result.depth, depth);
          result.overlapping += depth > 1e-6;
        }
    return result;
  }

  void
  make_scene(Scene &scene)
  {
    softface_tests::make_block(scene, 6000, 1);
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && std::abs(face->center()[2]) < 1e-9)
          face->set_boundary_id(13);
    scene.segments = {{"jaw", {}, {12}, {}}, {"base", {}, {13}, {}}};
    scene.setup();
    softface_tests::apply_effect(scene,
                                 "separated lips",
                                 {{"Slit point", "40, 40, 40"},
                                  {"Region", "-1, 50, -1, 81, 39, 41"}});
  }

  // The jaw closes by 3 mm, or (tilting) moves down 1 mm and turns by 4
  // degrees about the y axis through the slit's centre (40, 40, 40), lifting
  // the slit's front (x = 0) by 2.8 mm and pressing its back. About an axis
  // in the slit the lips hardly slide along each other: the pairs are node
  // to node, valid while the sliding is small against the cells.
  Vector<double>
  solve(Models::Interface &model,
        const Scene       &scene,
        const bool         tilting = false)
  {
    Planning planning;
    planning.set_motion(0,
                        tilting ? RigidMotion(softface_tests::vec(0., 0., -1.),
                                              softface_tests::vec(0., 1., 0.),
                                              4.,
                                              Point<3>(40., 40., 40.)) :
                                  RigidMotion(softface_tests::vec(0., 0., -3.),
                                              softface_tests::vec(0., 0., 1.),
                                              0.,
                                              Point<3>()));
    model.setup(scene);
    Vector<double> u;
    model.solve(planning.prescribed_displacement(scene), u);
    return u;
  }
} // namespace

SOFTFACE_TEST(effects_separated_lips)
{
  Scene scene;
  make_scene(scene);
  softface_tests::print("vertex pairs across the slit",
                        scene.effects.vertex_constraints.size());

  // The slit alone: the upper lip sinks into the lower one.
  {
    Scene cut;
    make_scene(cut);
    const auto pairs = cut.effects.vertex_constraints;
    cut.effects.vertex_constraints.clear();
    Models::LinearFEM fem;
    fem.set_solver("direct", 0.);
    const Vector<double> u         = solve(fem, cut);
    cut.effects.vertex_constraints = pairs;
    const Check c                  = check(cut, u);
    softface_tests::check_above("slit without contact: linear fem, deepest "
                                "overlap of two cells (mm)",
                                c.depth,
                                0.1,
                                2);
  }

  Models::LinearFEM fem;
  fem.set_solver("cg amg", 1e-12);
  Models::MassTensor mtm;
  mtm.set_scheme(true, 1e-8, 10, true);
  Models::NonlinearFEM nonlinear;
  nonlinear.set_options("neo-hooke", "direct");
  Models::MassSpring msm;
  msm.set_stop_threshold(1e-5);
  for (const auto &[name, model] :
       std::vector<std::pair<std::string, Models::Interface *>>{
         {"linear fem", &fem},
         {"mass tensor", &mtm},
         {"nonlinear fem", &nonlinear},
         {"mass spring", &msm}})
    {
      const Check c = check(scene, solve(*model, scene));
      softface_tests::check_above(name + ": smallest gap across the slit (mm)",
                                  c.smallest_gap,
                                  -1e-9,
                                  1);
      softface_tests::check_equal(name + ": overlapping cell pairs",
                                  c.overlapping,
                                  0);
    }

  // Tilting: the front opens, the back presses.
  Models::LinearFEM direct;
  direct.set_solver("direct", 0.);
  Models::NonlinearFEM nonlinear_amg;
  nonlinear_amg.set_options("neo-hooke", "cg amg");
  const double n_pairs = scene.effects.vertex_constraints.size();
  const double cell_size =
    80. / std::cbrt(scene.triangulation.n_active_cells() / 6.);
  for (const auto &[name, model] :
       std::vector<std::pair<std::string, Models::Interface *>>{
         {"linear fem (direct)", &direct},
         {"linear fem (cg amg)", &fem},
         {"nonlinear fem (cg amg)", &nonlinear_amg},
         {"mass tensor", &mtm}})
    {
      const Check c = check(scene, solve(*model, scene, true));
      softface_tests::check_above("tilting: " + name +
                                    ": smallest gap across the slit (mm)",
                                  c.smallest_gap,
                                  -1e-9,
                                  1);
      // Node to node: where the lips press and slide a little, faces may
      // cross by a tiny fraction of a cell between the pairs.
      softface_tests::check_below("tilting: " + name +
                                    ": deepest overlap / cell size",
                                  c.depth / cell_size,
                                  1e-3);
      for (const auto &d : model->statistics().details)
        if (d.name == "contact constraints holding")
          softface_tests::check_within("tilting: " + name +
                                         ": fraction of pairs in contact",
                                       d.value / n_pairs,
                                       0.05,
                                       0.95);
    }
}

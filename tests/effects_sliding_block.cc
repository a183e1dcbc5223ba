// Sliding contact against the closed form: a block of tissue (80 mm,
// Poisson's ratio 0) between a plate glued to its top face and a base it
// slides on. The plate moves down by d and sideways by s, the base up by t.
// With Poisson's ratio 0 the answer is affine for every law softface has:
//   u = (s, 0, t + (-d - t) z / L),
// the block sliding on the base as a whole (linear elements and the
// converged mass tensor model hold it to the solver's tolerance, the
// nonlinear laws too: with lambda = 0 a uniaxial stretch has no lateral
// stress). Glued to the base instead, its bottom cannot slide. Unilateral
// contact pressed gives the same answer; lifted (the plate moving up), the
// block leaves the base and moves rigidly with the plate, exactly, in every
// model (the springs too). Turned as a whole (block, plate and base motions),
// so that the base's normal has three non-zero components and every term of
// a sliding constraint counts, the answer is the flat one turned.

#include <softface/core/planning.h>
#include <softface/models/linear_fem.h>
#include <softface/models/mass_spring.h>
#include <softface/models/mass_tensor.h>
#include <softface/models/nonlinear_fem.h>

#include <deal.II/grid/grid_tools.h>
#include <deal.II/physics/transformations.h>

#include "effects.h"
#include "tests.h"

using namespace softface;

namespace
{
  constexpr double L = 80., s = 3., t = 1.; // mm

  // The block with its bottom face (boundary id 13) on the base segment,
  // the top (12) on the plate; sliding or glued.
  // A rotation about an oblique axis: the turned base's normal has no zero
  // component.
  const Tensor<2, 3> turn =
    Physics::Transformations::Rotations::rotation_matrix_3d(
      Tensor<1, 3>(
        {1. / std::sqrt(14.), 2. / std::sqrt(14.), 3. / std::sqrt(14.)}),
      0.5);

  void
  make_scene(Scene              &scene,
             const bool          sliding,
             const bool          unilateral,
             const Tensor<2, 3> &rotation = unit_symmetric_tensor<3>())
  {
    softface_tests::make_block(scene, 3000, 1);
    scene.material.poissons_ratio = 0.;
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && std::abs(face->center()[2]) < 1e-9)
          face->set_boundary_id(13);
    GridTools::transform(
      [&](const Point<3> &x) { return Point<3>(rotation * x); },
      scene.triangulation);
    scene.segments = {{"plate", {}, {12}, {}}, {"base", {}, {13}, {}}};
    scene.setup();
    if (sliding)
      softface_tests::apply_effect(
        scene,
        "sliding contact",
        {{"Segment", "base"}, {"Unilateral", unilateral ? "true" : "false"}});
  }

  Vector<double>
  planned(const Scene        &scene,
          const double        d,
          const Tensor<2, 3> &rotation = unit_symmetric_tensor<3>())
  {
    Planning planning;
    planning.set_motion(0,
                        RigidMotion(rotation * softface_tests::vec(s, 0., -d),
                                    softface_tests::vec(0., 0., 1.),
                                    0.,
                                    Point<3>()));
    planning.set_motion(1,
                        RigidMotion(rotation * softface_tests::vec(0., 0., t),
                                    softface_tests::vec(0., 0., 1.),
                                    0.,
                                    Point<3>()));
    return planning.prescribed_displacement(scene);
  }

  // Largest distance from u = (s, 0, t + (-d - t) z / L) (lifted: the
  // plate's motion (s, 0, -d) everywhere), turned by the scene's rotation:
  // u(R x) = R u_flat(x).
  double
  error(const Scene          &scene,
        const Vector<double> &u,
        const double          d,
        const bool            lifted,
        const Tensor<2, 3>   &rotation = unit_symmetric_tensor<3>())
  {
    double e = 0.;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      {
        const auto    &dofs = scene.vertex_dofs()[v];
        const Point<3> x =
          Point<3>(transpose(rotation) * scene.triangulation.get_vertices()[v]);
        const Tensor<1, 3> exact =
          rotation *
          softface_tests::vec(s, 0., lifted ? -d : t + (-d - t) * x[2] / L);
        for (unsigned int c = 0; c < 3; ++c)
          e = std::max(e, std::abs(u[dofs[c]] - exact[c]));
      }
    return e;
  }

  // The bottom face's largest sideways motion, its mean sideways motion
  // and its largest distance from the base (|u_z - t|).
  std::array<double, 3>
  bottom(const Scene &scene, const Vector<double> &u)
  {
    double       slide = 0., sum = 0., off = 0.;
    unsigned int n = 0;
    for (unsigned int v = 0; v < scene.n_vertices(); ++v)
      if (std::abs(scene.triangulation.get_vertices()[v][2]) < 1e-9)
        {
          const auto &dofs = scene.vertex_dofs()[v];
          slide            = std::max(slide, std::abs(u[dofs[0]]));
          sum += u[dofs[0]];
          ++n;
          off = std::max(off, std::abs(u[dofs[2]] - t));
        }
    return {{slide, sum / n, off}};
  }

  std::unique_ptr<Models::Interface>
  model(const std::string &name)
  {
    if (name == "linear fem")
      {
        auto fem = std::make_unique<Models::LinearFEM>();
        fem->set_solver("cg amg", 1e-12);
        return fem;
      }
    if (name == "mass tensor")
      {
        auto mtm = std::make_unique<Models::MassTensor>();
        mtm->set_scheme(true, 1e-11, 10, true);
        mtm->set_relaxation(1.8);
        return mtm;
      }
    if (name == "nonlinear fem")
      {
        auto nonlinear = std::make_unique<Models::NonlinearFEM>();
        nonlinear->set_options("neo-hooke", "direct");
        return nonlinear;
      }
    auto msm = std::make_unique<Models::MassSpring>();
    msm->set_stop_threshold(1e-7);
    return msm;
  }

  Vector<double>
  solve(const std::string  &name,
        const Scene        &scene,
        const double        d,
        const Tensor<2, 3> &rotation = unit_symmetric_tensor<3>())
  {
    const auto m = model(name);
    m->setup(scene);
    Vector<double> u;
    m->solve(planned(scene, d, rotation), u);
    return u;
  }
} // namespace

SOFTFACE_TEST(effects_sliding_block)
{
  const double d = 4.;

  // Off: glued to the base, the bottom cannot slide; the answer is far
  // from the sliding one (at the bottom by the whole sideways motion s).
  {
    Scene scene;
    make_scene(scene, false, false);
    softface_tests::check_above(
      "off: linear fem, max |u - sliding closed form| / s",
      error(scene, solve("linear fem", scene, d), d, false) / s,
      0.99);
  }

  // On, bilateral: every model against the closed form.
  Scene scene;
  make_scene(scene, true, false);
  // Every vertex of the bottom face (the side faces are not glued).
  unsigned int n_bottom = 0;
  for (unsigned int v = 0; v < scene.n_vertices(); ++v)
    n_bottom += std::abs(scene.triangulation.get_vertices()[v][2]) < 1e-9;
  softface_tests::check_equal("sliding vertices = vertices of the bottom face",
                              scene.effects.vertex_constraints.size(),
                              n_bottom);
  for (const std::string name : {"linear fem", "mass tensor", "nonlinear fem"})
    {
      const Vector<double> u = solve(name, scene, d);
      softface_tests::check_below("on: " + name +
                                    ", max |u - closed form| (mm)",
                                  error(scene, u, d, false),
                                  1e-7);
    }
  {
    // Springs are not elasticity: on the base exactly, sliding by about s.
    const Vector<double> u        = solve("mass spring", scene, d);
    const auto [slide, mean, off] = bottom(scene, u);
    softface_tests::check_below("on: mass spring, bottom's |u_z - t| (mm)",
                                off,
                                1e-12);
    softface_tests::check_within(
      "on: mass spring, bottom's mean sideways motion / s",
      mean / s,
      0.95,
      1.05);
    softface_tests::print("on: mass spring, max |u - closed form| (mm)",
                          error(scene, u, d, false),
                          2);
  }

  // Turned: the flat answer turned, for every model that holds the closed
  // form.
  {
    Scene turned;
    make_scene(turned, true, false, turn);
    for (const std::string name :
         {"linear fem", "mass tensor", "nonlinear fem"})
      softface_tests::check_below(
        "turned 0.5 rad about (1, 2, 3): " + name +
          ", max |u - closed form turned| (mm)",
        error(turned, solve(name, turned, d, turn), d, false, turn),
        1e-7);
  }

  // Only the base moves (up by t, the plate held): every model must carry
  // the sliding bottom with it (the mass spring model's load steps follow
  // the surface, not only the join points).
  for (const std::string name :
       {"linear fem", "mass tensor", "nonlinear fem", "mass spring"})
    {
      const auto m = model(name);
      m->setup(scene);
      Planning only_base;
      only_base.set_motion(1,
                           RigidMotion(softface_tests::vec(0., 0., t),
                                       softface_tests::vec(0., 0., 1.),
                                       0.,
                                       Point<3>()));
      Vector<double> u;
      m->solve(only_base.prescribed_displacement(scene), u);
      const auto [slide, mean, off] = bottom(scene, u);
      softface_tests::check_below("only the base moves: " + name +
                                    ", bottom's |u_z - t| (mm)",
                                  off,
                                  1e-9);
    }

  // Unilateral, pressed: the same answer; lifted: rigid with the plate.
  Scene one_sided;
  make_scene(one_sided, true, true);
  softface_tests::check_below(
    "unilateral, pressed: linear fem, max |u - closed form| (mm)",
    error(one_sided, solve("linear fem", one_sided, d), d, false),
    1e-7);
  for (const std::string name :
       {"linear fem", "mass tensor", "nonlinear fem", "mass spring"})
    {
      Scene lifted;
      make_scene(lifted, true, true);
      softface_tests::check_below(
        "unilateral, lifted 2 mm: " + name + ", max |u - plate motion| (mm)",
        error(lifted, solve(name, lifted, -2.), -2., true),
        name == "mass spring" ? 1e-3 : 1e-7);
    }
}

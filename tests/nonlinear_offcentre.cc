// The off-centre case (doc/results/nonlinear_solvers.md) against CalculiX
// NLGEOM (the same St. Venant-Kirchhoff equations on the same gmsh mesh,
// tests/data/offcentre_coarse/README.md): a bone box turned by 25 degrees
// and pushed 10 mm towards a held face, 16.7 mm at most.
// - CalculiX's increments at loads 0.35 and 0.575 (its last with no
//   tetrahedron inverted) are stable equilibria of softface's equations: the
//   residual is at the CSV's rounding, the tangent positive definite.
// - On CalculiX's path (the displacement ramped linearly) softface's SVK
//   equals CalculiX at both to 1e-4, and over the whole planning it gets at
//   least as far as 0.575.
// - On the default (rigid) path, where it stops, what the message says is
//   checked: the equilibrium at the load reached is stable, and the
//   tetrahedron it names is inverted in CalculiX's next increment.
// - Neo-Hooke reaches the whole planning with no tetrahedron inverted, and
//   KINSOL as the corrector gives the answer of softface's Newton loop.

#include <softface/fe/constrained_system.h>
#include <softface/fe/sparse_cholesky.h>

#include <map>

#include "nonlinear_runs.h"
#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  /// Whether the tangent of @p model at @p u is positive definite on the
  /// free DoFs (Cholesky; the join DoFs' rows and columns replaced by the
  /// identity).
  bool
  stable_at(const Models::NonlinearFEM &model,
            const Scene                &scene,
            const Vector<double>       &u,
            double                     *residual = nullptr)
  {
    Vector<double>       forces(u.size());
    SparseMatrix<double> tangent(model.sparsity_pattern());
    AssertThrow(model.evaluate(u, forces, &tangent),
                ExcMessage("an inverted tetrahedron"));
    ConstrainedSystem::eliminate_join_dofs(scene.join_dofs(), tangent);
    for (unsigned int i = 0; i < u.size(); ++i)
      if (scene.join_dofs()[i])
        tangent.diag_element(i) = 1.;
    if (residual != nullptr)
      *residual = ConstrainedSystem::free_norm(scene.join_dofs(), forces);
    SparseCholesky cholesky;
    return cholesky.refactorize(tangent);
  }

  /// det F of the P1 cell @p index under @p u.
  double
  volume_ratio(const Scene          &scene,
               const Vector<double> &u,
               const unsigned int    index)
  {
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      if (cell->active_cell_index() == index)
        {
          const Tetrahedron::Vertices x = Tetrahedron::vertices(cell);
          Tetrahedron::Vertices       y = x;
          for (unsigned int k = 0; k < 4; ++k)
            for (unsigned int c = 0; c < 3; ++c)
              y[k][c] += u[scene.vertex_dofs()[cell->vertex_index(k)][c]];
          return Tetrahedron::signed_volume(y) / Tetrahedron::signed_volume(x);
        }
    AssertThrow(false, ExcMessage("no cell " + std::to_string(index)));
    return 0.;
  }

  Vector<double>
  calculix_at(const Scene &scene, const std::string &load)
  {
    return softface_tests::read_peer(
      scene,
      softface_tests::source_file(
        "data/offcentre_coarse/calculix_nl_displacements_" + load + ".csv"));
  }
} // namespace

SOFTFACE_TEST(nonlinear_offcentre)
{
  ParameterHandler prm;
  Scene            scene;
  const Planning   planning =
    softface_tests::read_scene("nonlinear_offcentre.prm", prm, scene);
  const Vector<double> prescribed = planning.prescribed_displacement(scene);
  softface_tests::print("largest bone displacement component (mm)",
                        prescribed.linfty_norm(),
                        3);

  // CalculiX's path (the displacement ramped linearly), at two of its
  // increments. Which of CalculiX's states are stable equilibria of the same
  // equations: the residual at its displacements and whether the tangent
  // there is positive definite (Cholesky).
  std::map<std::string, bool> stable;
  Models::NonlinearFEM        svk_model;
  svk_model.set_options("st venant-kirchhoff", "direct");
  svk_model.setup(scene);
  {
    for (const std::string load : {"0.3500000", "0.5750000"})
      {
        // The scale: the free forces of the same load's join motion alone
        // (free points not moved), linearised from 1 % of the motion: the
        // join motion alone inverts tetrahedra at these loads, where the
        // forces are not defined (a scale evaluated at the whole motion
        // would be whatever the evaluation summed before its first
        // inverted cell, and change with the cell order).
        Vector<double> join_motion = prescribed;
        join_motion *= 0.01;
        Vector<double> join_forces(prescribed.size());
        AssertThrow(svk_model.evaluate(join_motion, join_forces, nullptr),
                    ExcMessage("1 % of the join motion inverts a cell"));
        const double scale =
          ConstrainedSystem::free_norm(scene.join_dofs(), join_forces) / 0.01 *
          std::stod(load);
        double residual = 0.;
        stable[load] =
          stable_at(svk_model, scene, calculix_at(scene, load), &residual);
        softface_tests::check_below(
          "CalculiX at " + load.substr(0, 5) +
            ": free residual force / that of its join motion alone",
          residual / scale,
          2e-6);
        softface_tests::check_equal("CalculiX at " + load.substr(0, 5) +
                                      ": tangent positive definite (stable)",
                                    stable[load],
                                    1);
      }
  }
  softface_tests::NonlinearOptions on_calculix_path;
  on_calculix_path.law  = "st venant-kirchhoff";
  on_calculix_path.path = "linear";
  for (const std::string load : {"0.3500000", "0.5750000"})
    {
      auto options = on_calculix_path;
      options.load = std::stod(load);
      const auto svk =
        softface_tests::solve_nonlinear(scene, planning, options);
      softface_tests::check_equal("st venant-kirchhoff to " +
                                    load.substr(0, 5) + ": converged",
                                  svk.converged,
                                  1);
      softface_tests::check_below(
        "st venant-kirchhoff to " + load.substr(0, 5) +
          ": relative difference to CalculiX NLGEOM",
        softface_tests::relative_difference(svk.u, calculix_at(scene, load)),
        1e-4);
    }

  // The whole planning on CalculiX's path: at least as far as CalculiX's last
  // stable state with no tetrahedron inverted.
  {
    const auto svk =
      softface_tests::solve_nonlinear(scene, planning, on_calculix_path);
    softface_tests::check_above(
      "st venant-kirchhoff, whole planning on the linear path: load reached",
      svk.load,
      stable["0.5750000"] ? 0.575 : 0.35);
  }

  // On the default (rigid) path, with the stop's diagnosis checked
  // independently: the equilibrium at the load reached is stable, and the
  // tetrahedron the message names is one that CalculiX's next increment
  // (0.659) inverts.
  {
    softface_tests::NonlinearOptions options;
    options.law    = "st venant-kirchhoff";
    const auto svk = softface_tests::solve_nonlinear(scene, planning, options);
    softface_tests::print("st venant-kirchhoff, rigid path: load reached",
                          svk.load,
                          3);
    if (svk.converged)
      softface_tests::check_above("st venant-kirchhoff: smallest det F",
                                  softface_tests::min_volume_ratio(scene,
                                                                   svk.u),
                                  0.);
    else
      {
        deallog << "st venant-kirchhoff, rigid path: " << svk.message
                << std::endl;
        options.load = svk.load;
        const auto before =
          softface_tests::solve_nonlinear(scene, planning, options);
        softface_tests::check_equal("at the load reached: converged and stable",
                                    before.converged &&
                                      stable_at(svk_model, scene, before.u),
                                    1);
        softface_tests::check_equal(
          "the message says that equilibrium is stable",
          svk.message.find("At that load the equilibrium is stable") !=
            std::string::npos,
          1);
        // Named as the mesh file numbers it ("element N (line L)").
        const std::string named = "inverts a tetrahedron (";
        const auto        where = svk.message.find(named);
        unsigned int      cell  = numbers::invalid_unsigned_int;
        if (where != std::string::npos)
          for (unsigned int c = 0; c < scene.triangulation.n_active_cells();
               ++c)
            if (svk.message.compare(where + named.size(),
                                    scene.cell_name(c).size() + 4,
                                    scene.cell_name(c) + " at ") == 0)
              cell = c;
        softface_tests::check_equal("the message names a tetrahedron",
                                    cell != numbers::invalid_unsigned_int,
                                    1);
        softface_tests::check_below(
          "its volume ratio in CalculiX's increment at 0.659",
          volume_ratio(scene, calculix_at(scene, "0.6593750"), cell),
          0.);
      }
  }

  // Neo-Hooke, corrected by softface's loop and by KINSOL.
  {
    const auto newton = softface_tests::solve_nonlinear(
      scene, planning, "neo-hooke", "rigid", "tangent", "newton");
    const auto kinsol = softface_tests::solve_nonlinear(
      scene, planning, "neo-hooke", "rigid", "tangent", "kinsol");
    softface_tests::check_equal("neo-hooke, newton: converged",
                                newton.converged,
                                1);
    softface_tests::check_equal("neo-hooke, kinsol: converged",
                                kinsol.converged,
                                1);
    softface_tests::check_above("neo-hooke: smallest det F",
                                softface_tests::min_volume_ratio(scene,
                                                                 newton.u),
                                0.);
    unsigned int join_mismatches = 0;
    for (unsigned int i = 0; i < prescribed.size(); ++i)
      join_mismatches +=
        scene.join_dofs()[i] && std::abs(newton.u[i] - prescribed[i]) > 1e-12;
    softface_tests::check_equal("neo-hooke: join DoFs not as planned",
                                join_mismatches,
                                0);
    softface_tests::check_below(
      "neo-hooke: kinsol against newton (relative max difference)",
      softface_tests::relative_difference(kinsol.u, newton.u),
      1e-6);
  }
}

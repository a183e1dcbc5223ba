// Hard cases stay numerically stable: the largest motion of Mollemans et
// al. 2007 (16.7 mm) and 25 mm, Poisson's ratio 0.49, and a mesh with sliver
// tetrahedra. Each either converges to a finite answer with the join points
// where planned, or stops with an error that names the load step, the
// residual and the reason; never NaN, never a hang (the test would time out).
// On an indefinite tangent (St. Venant-Kirchhoff's first 16.7 mm step, as
// the Cholesky factorisation finds) CG reports it too, from the negative
// curvature it meets, instead of running to its iteration limit (with
// 'Indefinite tangent = cut back'; by default LU solves such a system).

#include <deal.II/grid/grid_tools.h>

#include <softface/core/error.h>
#include <softface/core/tetrahedron.h>
#include <softface/models/nonlinear_fem.h>

#include <sstream>

#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  void
  run_case(const std::string    &name,
           const Scene          &scene,
           const Vector<double> &prescribed,
           const std::string    &law)
  {
    Models::NonlinearFEM model;
    model.set_options(law, "direct");
    model.setup(scene);
    Vector<double>    u;
    const std::string prefix = name + " (" + law + ")";
    try
      {
        model.solve(prescribed, u);
      }
    catch (const Error &e)
      {
        const std::string m = e.what();
        deallog << prefix << ": stopped: " << m << std::endl;
        softface_tests::check_equal(prefix +
                                      ": the message names the load step "
                                      "and the residual",
                                    m.find("load step") != std::string::npos &&
                                      m.find("residual") != std::string::npos,
                                    1);
        return;
      }
    unsigned int not_finite = 0, join_mismatches = 0;
    for (unsigned int i = 0; i < u.size(); ++i)
      {
        not_finite += !std::isfinite(u[i]);
        join_mismatches += (scene.join_dofs()[i] && u[i] != prescribed[i]);
      }
    deallog << prefix << ": converged in " << model.report().load_steps
            << " load steps, " << model.report().newton_iterations
            << " Newton iterations, " << model.report().cutbacks << " cut-backs"
            << std::endl;
    softface_tests::check_equal(prefix + ": entries that are not finite",
                                not_finite,
                                0);
    softface_tests::check_equal(prefix + ": join DoFs not as planned",
                                join_mismatches,
                                0);
    softface_tests::print(prefix + ": max |u| (mm)", u.linfty_norm(), 4);
  }

  /// The reason of the first failed load step, from the progress lines.
  std::string
  first_failure(const Scene          &scene,
                const Vector<double> &prescribed,
                const std::string    &solver)
  {
    // The solvers' own detection, not the LU that takes over by default.
    ParameterHandler prm;
    Models::NonlinearFEM::declare_parameters(prm);
    prm.set("Material law", "st venant-kirchhoff");
    prm.set("Solver", solver);
    prm.set("Initial load increment", "1");
    prm.set("Indefinite tangent", "cut back");
    Models::NonlinearFEM model;
    model.parse_parameters(prm);
    std::ostringstream progress;
    model.setup(scene, {&progress, MPI_COMM_WORLD, nullptr});
    Vector<double> u;
    try
      {
        model.solve(prescribed, u);
      }
    catch (const Error &)
      {}
    std::istringstream lines(progress.str());
    for (std::string line; std::getline(lines, line);)
      if (line.find("failed (") != std::string::npos)
        return line;
    return "";
  }
} // namespace

SOFTFACE_TEST(nonlinear_hard_cases)
{
  Scene scene;
  softface_tests::make_cube_scene(scene, 8000);
  for (const std::string law : {"neo-hooke", "st venant-kirchhoff"})
    for (const double lift : {16.7, 25.})
      run_case(softface_tests::rounded(lift) + " mm",
               scene,
               softface_tests::move_bone(scene, Point<3>(0, 0, lift)),
               law);

  {
    const Vector<double> prescribed =
      softface_tests::move_bone(scene, Point<3>(0, 0, 16.7));
    for (const std::string solver : {"direct", "cg amg"})
      {
        const std::string line = first_failure(scene, prescribed, solver);
        deallog << "st venant-kirchhoff, 16.7 mm, " << solver
                << ": first failure:" << line << std::endl;
        softface_tests::check_equal(
          "st venant-kirchhoff, 16.7 mm, " + solver +
            ": it names the tangent not positive definite",
          line.find("the tangent is not positive definite") !=
            std::string::npos,
          1);
      }
  }

  Scene incompressible;
  incompressible.material.poissons_ratio = 0.49;
  softface_tests::make_cube_scene(incompressible, 8000);
  run_case("nu = 0.49, 6 mm",
           incompressible,
           softface_tests::move_bone(incompressible, Point<3>(0, 0, 6)),
           "neo-hooke");

  // Slivers: interior vertices pushed pseudo-randomly by the largest
  // fraction of the grid spacing (tried from 40% down) that inverts no cell.
  Scene sliver;
  sliver.segments  = {{"fixed", {}, {Mesh::cube_outer_face}, {}},
                      {"bone", {Mesh::cube_inner_id}, {}, {}}};
  double amplitude = 0.40;
  for (;; amplitude -= 0.02)
    {
      Mesh::CubeParameters cube;
      cube.target_n_tetrahedra = 8000;
      Mesh::generate_cube(cube, sliver.triangulation);
      GridTools::transform(
        [amplitude](const Point<3> &x) {
          const bool interior = x[0] > 0 && x[0] < 80 && x[1] > 0 &&
                                x[1] < 80 && x[2] > 0 && x[2] < 80 &&
                                !(x[0] >= 35 && x[0] <= 45 && x[1] >= 35 &&
                                  x[1] <= 45 && x[2] >= 35 && x[2] <= 45);
          if (!interior)
            return x;
          const double h = 80. / 11;
          return x + amplitude * h *
                       Point<3>(std::sin(12.9898 * x[0] + 78.233 * x[1]),
                                std::sin(39.3468 * x[1] + 11.135 * x[2]),
                                std::sin(73.156 * x[2] + 52.235 * x[0]));
        },
        sliver.triangulation);
      try
        {
          sliver.setup();
          break;
        }
      catch (const Error &)
        {}
    }
  double worst = 1e300;
  for (const auto &cell : sliver.triangulation.active_cell_iterators())
    {
      const auto x       = Tetrahedron::vertices(cell);
      double     longest = 0.;
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int b = 0; b < a; ++b)
          longest = std::max(longest, x[a].distance(x[b]));
      worst =
        std::min(worst, Tetrahedron::signed_volume(x) / std::pow(longest, 3));
    }
  softface_tests::print("sliver mesh: amplitude (grid spacings)", amplitude);
  softface_tests::check_below("sliver mesh: smallest volume / longest "
                              "edge^3 (a regular tetrahedron has 0.118)",
                              worst,
                              1e-3);
  run_case("slivers, 6 mm",
           sliver,
           softface_tests::move_bone(sliver, Point<3>(0, 0, 6)),
           "neo-hooke");
}

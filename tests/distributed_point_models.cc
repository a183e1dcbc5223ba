// The mass tensor and mass spring models on several MPI ranks,
// run by ctest on 2 and 3 ranks (distributed_point_models.mpirun=N.output).
// Each rank sweeps the points of its range of blocks, the colours in turn
// with an exchange after each: the serial sweep, update for update. So the
// ranks' answer equals the serial model's (MPI_COMM_SELF in the same run)
// to the last bit, after as many sweeps, and stops where it stops:
// Each point's mass tensors are held by one rank only.
// - the mass tensor model converged fully (gradient 1e-9 mm per sweep),
//   which is linear FEM's answer, its converged equivalent; with its default
//   stop (the criterion of Mollemans et al. 2007 checked by 'Stop distance',
//   0.1 mm) within 0.1 mm of it: the paper's cube with the bone turned, without
//   the active set and in damped Jacobi order too (and its precision against
//   the converged answer, which a rank solves from the whole tensors), the cube
//   held on one face only (a rank owns no join point, and the held face lies on
//   one rank), the shared gmsh cube lifted 6 mm, two tissues under gravity;
// - the mass spring model on the same scenes, and on a cube whose bone
//   moves near its held face, where the ranks' blocks are shared again
//   between the load steps by each step's updates (the same answer and
//   sweeps).
// On the ranks, the updates of the rank each colour waits for, summed over
// the sweeps' colours, lie between the busiest rank's and all updates.

#include <softface/core/displacement.h>
#include <softface/models/linear_fem.h>
#include <softface/models/mass_spring.h>
#include <softface/models/mass_tensor.h>
#include <softface/models/point_exchange.h>

#include <algorithm>
#include <array>
#include <sstream>

#include "effects.h"
#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface_tests;

namespace
{
  /// The last run on several ranks: its slowest rank's updates colour by
  /// colour, its busiest rank's updates, every update.
  std::array<unsigned long long, 3> ranks_updates;

  /// The model's answer on @p communicator; on several ranks it must say
  /// that it shared the work (its "MPI ranks" figure).
  Vector<double>
  solve(Models::Interface    &model,
        const MPI_Comm        communicator,
        const Scene          &scene,
        const Vector<double> &prescribed)
  {
    model.setup(scene, {nullptr, communicator, nullptr});
    Vector<double> u;
    model.solve(prescribed, u);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    if (n_ranks > 1)
      {
        bool shared = false;
        for (const auto &detail : model.statistics().details)
          shared |= detail.name == "MPI ranks" && detail.value == n_ranks;
        if (!shared)
          throw std::runtime_error("the model did not run on the ranks");
        const auto figure = [&](const std::string &name) {
          for (const auto &detail : model.statistics().details)
            if (detail.name == name)
              return static_cast<unsigned long long>(detail.value);
          throw std::runtime_error("no figure '" + name + "'");
        };
        ranks_updates = {
          {figure("slowest rank's point updates, colour by colour"),
           figure("busiest rank's point updates"),
           figure("point updates")}};
      }
    return u;
  }

  /// Each colour of a sweep waits for the rank with the most updates in
  /// it: summed colour by colour, those are at least the busiest rank's
  /// total and at most every update (the last run on the ranks).
  void
  check_colour_updates()
  {
    const auto [slowest, busiest, total] = ranks_updates;
    deallog << "  slowest rank's updates, colour by colour: " << slowest
            << " (between " << busiest << " and " << total << ")" << std::endl;
    if (!(slowest >= busiest && slowest <= total))
      throw std::runtime_error("the slowest rank's updates are out of bounds");
  }

  Vector<double>
  linear_fem(const Scene &scene, const Vector<double> &prescribed)
  {
    Models::LinearFEM model;
    model.set_solver("cg amg", 1e-12);
    return solve(model, MPI_COMM_SELF, scene, prescribed);
  }

  /// The ranks' answer and sweeps against the serial model's: the same
  /// sweep, update for update, so equal to the last bit.
  void
  check_same_as_serial(const Scene &scene,
                       const Vector<double> (&answer)[2],
                       const unsigned int (&sweeps)[2])
  {
    check_equal(
      "  largest difference, ranks to serial (mm)",
      Displacement::free_vertex_difference(scene, answer[1], answer[0]).max,
      0.);
    check_equal("  sweeps on the ranks, serial " + std::to_string(sweeps[0]),
                sweeps[1],
                sweeps[0]);
  }

  /// The mass tensor model on one rank and on all, against linear FEM;
  /// with @p precision its precision against its converged answer too.
  void
  compare_mass_tensor(const std::string    &name,
                      const Scene          &scene,
                      const Vector<double> &prescribed,
                      const bool            converge_fully,
                      const bool            active_set = true,
                      const bool            precision  = false)
  {
    const Vector<double>      exact = linear_fem(scene, prescribed);
    Vector<double>            answer[2];
    unsigned int              sweeps[2];
    double                    precision_max[2];
    std::vector<unsigned int> holders(scene.triangulation.n_vertices(), 0);
    for (const unsigned int on_ranks : {0u, 1u})
      {
        Models::MassTensor model;
        model.set_scheme(true, converge_fully ? 0. : 1e-3, 10, active_set);
        model.set_report_precision(precision);
        answer[on_ranks]        = solve(model,
                                 on_ranks ? MPI_COMM_WORLD : MPI_COMM_SELF,
                                 scene,
                                 prescribed);
        sweeps[on_ranks]        = model.statistics().iterations;
        precision_max[on_ranks] = model.report().precision_max;
        if (on_ranks)
          for (unsigned int j = 0; j < model.n_points(); ++j)
            holders[j] = model.holds_tensors(j);
      }
    deallog << name << (converge_fully ? ", converged" : ", default stop")
            << ':' << std::endl;
    // Each point's tensors are held by one rank.
    Utilities::MPI::sum(holders, MPI_COMM_WORLD, holders);
    check_equal("  points whose tensors no rank or several ranks hold",
                std::count_if(holders.begin(),
                              holders.end(),
                              [](const unsigned int h) { return h != 1; }),
                0);
    if (precision)
      check_above("  precision on one rank (mm)", precision_max[0], 1e-9, 2);
    if (precision)
      check_below("  precision (largest distance to the converged answer, "
                  "mm), ranks against serial",
                  std::abs(precision_max[1] - precision_max[0]),
                  1e-12 * (1. + precision_max[0]));
    check_below(
      "  largest distance to linear fem (mm)",
      Displacement::free_vertex_difference(scene, answer[1], exact).max,
      converge_fully ? 1e-5 : 0.1);
    check_same_as_serial(scene, answer, sweeps);
    check_colour_updates();
  }

  /// The mass spring model on one rank and on all.
  void
  compare_mass_spring(const std::string    &name,
                      const Scene          &scene,
                      const Vector<double> &prescribed,
                      const double          threshold,
                      const bool            expect_rebalance = false)
  {
    Vector<double> answer[2];
    unsigned int   sweeps[2];
    unsigned int   load_steps = 0, rebalances = 0;
    for (const unsigned int on_ranks : {0u, 1u})
      {
        Models::MassSpring model;
        model.set_stop_threshold(threshold);
        answer[on_ranks] = solve(model,
                                 on_ranks ? MPI_COMM_WORLD : MPI_COMM_SELF,
                                 scene,
                                 prescribed);
        sweeps[on_ranks] = model.statistics().iterations;
        load_steps       = model.report().load_steps;
        rebalances       = model.report().rebalances;
      }
    std::ostringstream stop;
    stop << threshold;
    deallog << name << ", mass spring, stop threshold " << stop.str()
            << " mm:" << std::endl;
    print("  largest |u_i| (mm)", answer[1].linfty_norm());
    deallog << "  load steps: " << load_steps << std::endl;
    if (expect_rebalance)
      check_above("  load steps after which the ranks' blocks changed",
                  rebalances,
                  1);
    else
      deallog << "  load steps after which the ranks' blocks changed: "
              << rebalances << std::endl;
    check_same_as_serial(scene, answer, sweeps);
    check_colour_updates();
  }

  /// Who owns which points of a point model on the ranks.
  PointExchange
  point_owners(const PointMesh &mesh)
  {
    const BlockColouring colouring(mesh.n_points(),
                                   mesh.row_start,
                                   mesh.neighbour);
    return PointExchange(colouring, mesh, MPI_COMM_WORLD);
  }
} // namespace

SOFTFACE_TEST(distributed_point_models)
{
  deallog << "ranks: " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
          << std::endl;

  Scene cube;
  make_cube_scene(cube, 8000);
  const Vector<double> turned = move_bone(cube, Point<3>(3, 0, 1), 10.);
  compare_mass_tensor("cube, turned", cube, turned, true);
  compare_mass_tensor("cube, turned", cube, turned, false, true, true);
  compare_mass_tensor(
    "cube, turned, no active set", cube, turned, false, false);
  // Jacobi order (damped) on the ranks: an exchange of every colour after
  // each sweep.
  {
    const Vector<double> exact = linear_fem(cube, turned);
    Vector<double>       answer[2];
    unsigned int         sweeps[2];
    for (const unsigned int on_ranks : {0u, 1u})
      {
        Models::MassTensor model;
        model.set_scheme(false, 1e-4, 10, true);
        model.set_relaxation(0.6);
        answer[on_ranks] =
          solve(model, on_ranks ? MPI_COMM_WORLD : MPI_COMM_SELF, cube, turned);
        sweeps[on_ranks] = model.statistics().iterations;
      }
    deallog << "cube, turned, jacobi order, damped:" << std::endl;
    check_below(
      "  largest distance to linear fem (mm)",
      Displacement::free_vertex_difference(cube, answer[1], exact).max,
      0.1);
    check_same_as_serial(cube, answer, sweeps);
  }

  // Held on one face only, the bone moved: with the points' blocks in ranges,
  // a rank owns no join point, and the held face is one rank's.
  Scene one_face;
  make_cube_held_at_bottom(one_face, 8000);
  {
    const PointMesh     mesh(one_face, "test");
    const PointExchange points    = point_owners(mesh);
    bool                owns_join = false, owns_fixed = false;
    for (unsigned int v = 0; v < one_face.n_vertices(); ++v)
      {
        const unsigned int p       = one_face.vertex_dofs()[v][0] / 3;
        const unsigned int segment = one_face.vertex_segment()[v];
        if (points.owns(p) && segment != numbers::invalid_unsigned_int)
          {
            owns_join = true;
            owns_fixed |= segment == 0;
          }
      }
    check_above("cube held at z = 0: ranks that own no join point",
                Utilities::MPI::sum(int(!owns_join), MPI_COMM_WORLD),
                1);
    check_equal("cube held at z = 0: ranks that own a point of the held face",
                Utilities::MPI::sum(int(owns_fixed), MPI_COMM_WORLD),
                1);
  }
  compare_mass_tensor("cube held at z = 0, bone moved",
                      one_face,
                      move_bone(one_face, Point<3>(2, 0, 3), 5.),
                      false);

  ParameterHandler     prm;
  Scene                gmsh;
  const Vector<double> lift = read_peer_scene(prm, gmsh);
  compare_mass_tensor("gmsh cube30k, lifted", gmsh, lift, false);

  Scene layered;
  make_two_tissue_cube(layered);
  compare_mass_tensor("two tissues under gravity",
                      layered,
                      move_bone(layered, Point<3>(0, 0, 4)),
                      true);

  compare_mass_spring("cube, turned", cube, turned, 1e-5);
  compare_mass_spring("gmsh cube30k, lifted", gmsh, lift, 1e-4);
  // The bone moved near the held face: the updates gather on one side, and
  // the ranks' blocks are shared again between the load steps.
  Scene one_face_finer;
  make_cube_held_at_bottom(one_face_finer, 30000);
  compare_mass_spring("cube held at z = 0, 30k, bone moved",
                      one_face_finer,
                      move_bone(one_face_finer, Point<3>(2, 0, 3), 5.),
                      1e-3,
                      /*expect_rebalance=*/true);
  compare_mass_spring("two tissues under gravity",
                      layered,
                      move_bone(layered, Point<3>(0, 0, 4)),
                      1e-5);
}

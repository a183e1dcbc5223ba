// The nonlinear FEM model on several MPI ranks, run by ctest on 2
// and 3 ranks (distributed_nonlinear_fem.mpirun=N.output). Each rank
// evaluates its own cells into a distributed tangent solved by CG with ML;
// Newton's vectors are whole on every rank. The answer must equal the
// serial model's (MPI_COMM_SELF in the same run) to Newton's tolerance:
// relative 1e-8 with a residual tolerance of 1e-10, both with the same
// load steps and cut-backs, on
// - the cube of Mollemans et al. 2007, the bone turned by 10 degrees and
//   moved (cell order and METIS), and on the rigid load path;
// - the cube held on one face only (a rank owns no join point);
// - the shared gmsh cube (tests/data/cube30k) lifted 6 mm;
// - two tissues under gravity;
// - a motion large enough that load steps fail and are cut back (each
//   failure decided alike on all ranks);
// the quadratic reference model (its own layout on the ranks' mesh) on the
// cube, on two tissues under gravity, on METIS's parts of the coarsest cube
// (114 of its 162 cells carried whole by two segments: missing that rule on
// the ranks made 3 Newton iterations where serially there are none) and of
// a cube whose segments share vertices, one on boundary id 0, and its
// degree-1 form against the
// P1 model on the ranks and started near that answer (its vertex values,
// moved into the model's numbering: fewer Newton iterations than from rest,
// as serially, with METIS's parts); and what is not distributed (St.
// Venant-Kirchhoff's stability test, the direct solver) runs whole on every
// rank and says so. A solve that cannot reach its load fails on every rank with
// the same message.

#include <softface/core/error.h>
#include <softface/models/nonlinear_fem.h>
#include <softface/models/reference_fem.h>

#include "effects.h"
#include "peer.h"
#include "scenes.h"
#include "tests.h"

#include <set>

using namespace softface_tests;

namespace
{
  struct Options
  {
    std::string law               = "neo-hooke";
    std::string solver            = "cg amg";
    std::string minimum_increment = "0.001";
    std::string partitioner       = "cell order";
    /// The reference model of this degree instead (0: nonlinear fem).
    unsigned int reference_degree = 0;
    /// The join DoFs' motion at a load (null: the final one scaled).
    std::function<Vector<double>(double)> path;
    /// Vertex values to start Newton from (null: none).
    const Vector<double> *guess = nullptr;
  };

  struct Outcome
  {
    Vector<double> u;
    unsigned int   load_steps = 0, cutbacks = 0, newton = 0;
    std::string    ranks_detail;
  };

  Outcome
  solve(const MPI_Comm        communicator,
        const Scene          &scene,
        const Vector<double> &prescribed,
        const Options        &options)
  {
    ParameterHandler prm;
    Models::ReferenceFEM::declare_parameters(prm);
    prm.set("Material law", options.law);
    prm.set("Solver", options.solver);
    prm.set("Indefinite tangent", "cut back");
    prm.set("Linear tolerance", "1e-8");
    prm.set("Minimum load increment", options.minimum_increment);
    std::unique_ptr<Models::NonlinearElasticity> model_pointer;
    if (options.reference_degree > 0)
      {
        auto reference = std::make_unique<Models::ReferenceFEM>();
        reference->parse_parameters(prm);
        reference->set_degree(options.reference_degree);
        model_pointer = std::move(reference);
      }
    else
      {
        model_pointer = std::make_unique<Models::NonlinearFEM>();
        model_pointer->parse_parameters(prm);
      }
    Models::NonlinearElasticity &model = *model_pointer;
    model.setup(scene,
                {nullptr,
                 communicator,
                 std::make_shared<SharedDistributedLayout>(
                   communicator,
                   DistributedLayout::parse_partitioner(options.partitioner))});
    Outcome outcome;
    model.solve(prescribed, outcome.u, {options.path, options.guess});
    outcome.load_steps = model.report().load_steps;
    outcome.cutbacks   = model.report().cutbacks;
    outcome.newton     = model.report().newton_iterations;
    for (const auto &detail : model.statistics().details)
      if (detail.name == "MPI ranks")
        outcome.ranks_detail =
          detail.text.empty() ? std::to_string(int(detail.value)) : detail.text;
    return outcome;
  }

  /// The model on one rank and on all: the same answer and decisions.
  void
  compare(const std::string    &name,
          const Scene          &scene,
          const Vector<double> &prescribed,
          const Options        &options = Options())
  {
    const Outcome serial = solve(MPI_COMM_SELF, scene, prescribed, options);
    const Outcome ranks  = solve(MPI_COMM_WORLD, scene, prescribed, options);
    deallog << name << ':' << std::endl;
    deallog << "  MPI ranks: " << ranks.ranks_detail << std::endl;
    check_below("  relative difference to the serial model",
                relative_difference(ranks.u, serial.u),
                1e-8);
    print("  largest |u_i| (mm)", ranks.u.linfty_norm());
    deallog << "  load steps: serial " << serial.load_steps << ", ranks "
            << ranks.load_steps << "; cut-backs: serial " << serial.cutbacks
            << ", ranks " << ranks.cutbacks << std::endl;
    if (serial.load_steps != ranks.load_steps ||
        serial.cutbacks != ranks.cutbacks)
      throw std::runtime_error("the ranks stepped the load otherwise");
    // CG's answers differ within its tolerance: an iteration more or less.
    deallog << "  Newton iterations: serial " << serial.newton << ", ranks "
            << ranks.newton << std::endl;
    check_below("  Newton iterations, ranks minus serial",
                std::abs(double(ranks.newton) - serial.newton),
                1.);
  }
} // namespace

SOFTFACE_TEST(distributed_nonlinear_fem)
{
  deallog << "ranks: " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
          << std::endl;

  Scene cube;
  make_cube_scene(cube, 8000);
  const Vector<double> turned = move_bone(cube, Point<3>(3, 0, 1), 10.);
  compare("cube, turned", cube, turned);
  {
    Options metis;
    metis.partitioner = "metis";
    compare("cube, turned, metis", cube, turned, metis);
  }
  {
    Options rigid;
    rigid.path = [&cube](const double load) {
      return move_bone(cube, Point<3>(3 * load, 0, load), 10. * load);
    };
    compare("cube, turned, rigid path", cube, turned, rigid);
  }

  Scene one_face;
  make_cube_held_at_bottom(one_face, 8000);
  compare("cube held at z = 0, bone moved",
          one_face,
          move_bone(one_face, Point<3>(2, 0, 3), 5.));

  ParameterHandler     prm;
  Scene                gmsh;
  const Vector<double> lift = read_peer_scene(prm, gmsh);
  compare("gmsh cube30k, lifted", gmsh, lift);

  Scene layered;
  make_two_tissue_cube(layered);
  compare("two tissues under gravity",
          layered,
          move_bone(layered, Point<3>(0, 0, 4)));

  // A motion whose full load step fails: cut back, three times on one rank.
  Scene coarse;
  make_cube_scene(coarse, 3000);
  const Vector<double> far = move_bone(coarse, Point<3>(0, 0, 20), 60.);
  compare("coarse cube, lifted 20 mm and turned 60 degrees", coarse, far);

  // The quadratic reference (its own layout of quadratic tetrahedra on the
  // ranks' mesh) and, as a cross-check, its degree-1 form, which equals the
  // P1 model's answer.
  {
    Scene small;
    make_cube_scene(small, 3000);
    const Vector<double> small_turned =
      move_bone(small, Point<3>(3, 0, 1), 10.);
    Options quadratic;
    quadratic.reference_degree = 2;
    compare("reference fem, quadratic, cube, turned",
            small,
            small_turned,
            quadratic);
    compare("reference fem, quadratic, two tissues under gravity",
            layered,
            move_bone(layered, Point<3>(0, 0, 4)),
            quadratic);
    // Cells whose vertices are all join points of two or more segments are
    // carried whole by the bones: the serial count.
    const auto carried_cells = [](const Scene &scene) {
      unsigned int carried = 0;
      for (const auto &cell : scene.triangulation.active_cell_iterators())
        {
          std::set<unsigned int> segments;
          bool                   all_join = true;
          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int vertex = cell->vertex_index(v);
              all_join &= scene.join_dofs()[scene.vertex_dofs()[vertex][0]];
              segments.insert(scene.vertex_segment()[vertex]);
            }
          carried += all_join && segments.size() >= 2;
        }
      return carried;
    };
    // The coarsest cube, whose tissue is mostly one cell between the bone
    // and the held faces, on METIS's parts.
    Options quadratic_metis     = quadratic;
    quadratic_metis.partitioner = "metis";
    Scene thin;
    make_cube_scene(thin, 100);
    check_above("cells carried whole, coarsest cube (serial)",
                carried_cells(thin),
                1);
    compare("reference fem, quadratic, coarsest cube, metis",
            thin,
            move_bone(thin, Point<3>(0.3, 0, 0.3), 1.),
            quadratic_metis);
    // Segments that share vertices and one on boundary id 0, which only the
    // faces at the edge of a rank's part have there: the quadratic join DoFs
    // are decided from the cells at them.
    Scene shared;
    make_cube_with_shared_join_points(shared, 3000);
    deallog << "cells carried whole, shared join points (serial): "
            << carried_cells(shared) << std::endl;
    compare("reference fem, quadratic, segments sharing vertices, metis",
            shared,
            move_bone(shared, Point<3>(0.5, 0, 0.5), 2.),
            quadratic_metis);
    Options linear_elements;
    linear_elements.reference_degree = 1;
    const Outcome p1_reference =
      solve(MPI_COMM_WORLD, small, small_turned, linear_elements);
    const Outcome p1 = solve(MPI_COMM_WORLD, small, small_turned, Options());
    deallog << "reference fem, degree 1, on the ranks: MPI ranks "
            << p1_reference.ranks_detail << std::endl;
    check_below("  relative difference to nonlinear fem on the ranks",
                relative_difference(p1_reference.u, p1.u),
                1e-8);
    // Started near that answer (vertex values in the scene's numbering,
    // which the model's own layout numbers otherwise, on the ranks too with
    // METIS's parts): Newton takes fewer iterations than from rest,
    // serially and on the ranks alike.
    Vector<double> near = p1.u;
    for (unsigned int i = 0; i < near.size(); ++i)
      near[i] += 1e-3 * (double(i % 7) - 3.);
    Options from_near     = linear_elements;
    from_near.guess       = &near;
    from_near.partitioner = "metis";
    compare("reference fem, degree 1, from near the answer",
            small,
            small_turned,
            from_near);
    const Outcome guessed =
      solve(MPI_COMM_WORLD, small, small_turned, from_near);
    deallog << "  Newton iterations from rest: " << p1_reference.newton
            << std::endl;
    check_below("  Newton iterations from near the answer",
                guessed.newton,
                p1_reference.newton - 1.);
  }

  // Not distributed: whole on every rank, the same answer.
  {
    Options svk;
    svk.law = "st venant-kirchhoff";
    compare("cube, turned, st venant-kirchhoff", cube, turned, svk);
    Options direct;
    direct.solver = "direct";
    compare("cube, turned, direct solver", cube, turned, direct);
  }

  // Out of reach with a large minimum increment: every rank throws the
  // same message.
  {
    Options coarse_steps;
    coarse_steps.minimum_increment = "0.3";
    try
      {
        solve(MPI_COMM_WORLD, coarse, far, coarse_steps);
        throw std::runtime_error("the solve did not fail");
      }
    catch (const Error &e)
      {
        const std::string message = e.what();
        if (Utilities::MPI::broadcast(MPI_COMM_WORLD, message, 0) != message)
          throw std::runtime_error("the ranks' messages differ");
        deallog << "out of reach: " << message << std::endl;
      }
  }
}

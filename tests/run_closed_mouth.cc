// A phantom patient scanned with the mouth closed (tests/run_closed_mouth.prm):
// the upper and lower teeth touch on the occlusal plane and the lips are
// together, so a cut on the occlusal plane separates the jaws, and tissue
// between the lips and beside the teeth joins both. The mandible is advanced
// and set back by 5 mm; every model reaches full load on both plans, its join
// points where the plan puts them, nonlinear FEM within 2 mm of linear FEM.
//
// At 2 mm voxels a 3 mm detached margin alone would end at the centres of
// the voxel layer next to the occlusal kerf and detach nothing: the tissue
// in the kerf, pinned to both jaws 2 mm apart, would be sheared by the 5 mm
// advancement (nonlinear FEM would move a cheek point 8.2 mm, 6.5 mm from
// linear FEM, and stop at load 0.875 on 16000 tetrahedra). So the margin
// reaches at least one voxel beyond the kerf.
//
// The cells that join two bones: a cell whose four vertices are join points
// (in a kerf) moves as the bones move it, and the planning itself may turn it
// inside out (counted). It acts on prescribed DoFs only: linear FEM, the mass
// tensor and the mass spring model carry it without effect on the free
// points; nonlinear FEM leaves it out (its energy is not defined inside out).
// Cells with a free vertex left inverted are counted for each model: none for
// nonlinear FEM, which refuses any.

#include <softface/core/planning.h>
#include <softface/core/tetrahedron.h>

#include "run_scene.h"

#include <set>

SOFTFACE_TEST(run_closed_mouth)
{
  using namespace softface;
  Simulator simulator;
  softface_tests::run_patient_scene(simulator, "run_closed_mouth.prm", 10);
  const Scene &scene = simulator.scene();

  // The cells that join two bones: all four vertices join points (carried
  // by the bones), or some free.
  const auto           &segment_of = scene.vertex_segment();
  const auto           &dofs_of    = scene.vertex_dofs();
  std::vector<unsigned> carried, bridging;
  for (const auto &cell : scene.triangulation.active_cell_iterators())
    {
      std::set<unsigned int> segments;
      unsigned int           n_join = 0;
      for (const unsigned int v : cell->vertex_indices())
        if (segment_of[cell->vertex_index(v)] < scene.segments.size())
          {
            segments.insert(segment_of[cell->vertex_index(v)]);
            ++n_join;
          }
      if (segments.size() < 2)
        continue;
      if (n_join == 4)
        carried.push_back(cell->active_cell_index());
      else
        bridging.push_back(cell->active_cell_index());
    }
  softface_tests::check_within(
    "cells of join points of two segments", carried.size(), 1, 1e9, 9);
  softface_tests::check_within(
    "cells with join points of two segments and a free vertex",
    bridging.size(),
    1,
    1e9,
    9);

  // How many of @p cells the displacement @p u leaves inverted.
  const auto n_inverted = [&](const std::vector<unsigned int> &cells,
                              const Vector<double>            &u) {
    unsigned int n = 0;
    for (const unsigned int c : cells)
      {
        const auto cell = std::next(scene.triangulation.begin_active(), c);
        Tetrahedron::Vertices x;
        for (const unsigned int v : cell->vertex_indices())
          {
            x[v] = cell->vertex(v);
            for (unsigned int d = 0; d < 3; ++d)
              x[v][d] += u[dofs_of[cell->vertex_index(v)][d]];
          }
        n += Tetrahedron::signed_volume(x) <= 0.;
      }
    return n;
  };
  std::vector<unsigned int> all_cells(scene.triangulation.n_active_cells());
  for (unsigned int c = 0; c < all_cells.size(); ++c)
    all_cells[c] = c;
  std::vector<unsigned int> with_free_vertex;
  for (const auto &cell : scene.triangulation.active_cell_iterators())
    for (const unsigned int v : cell->vertex_indices())
      if (segment_of[cell->vertex_index(v)] >= scene.segments.size())
        {
          with_free_vertex.push_back(cell->active_cell_index());
          break;
        }

  const auto &plans = simulator.plannings().plans;
  softface_tests::check_equal("plans", plans.size(), 2);
  std::map<std::string, Vector<double>> planned;
  for (const auto &plan : plans)
    {
      const std::string name =
        plan.name == "planning" ? "advancement" : plan.name;
      planned[plan.name] = plan.planning.prescribed_displacement(scene);
      softface_tests::check_within(name +
                                     ": cells of join points the plan inverts",
                                   n_inverted(carried, planned[plan.name]),
                                   0,
                                   1e9,
                                   9);
    }

  unsigned int                                    n_runs = 0;
  std::map<std::string, const Report::ModelRun *> linear_fem;
  for (const auto &run : simulator.runs())
    if (run.model == "linear fem")
      linear_fem[run.planning] = &run;
  for (const auto &run : simulator.runs())
    {
      const std::string plan = run.planning.empty() ? "planning" : run.planning;
      const std::string label =
        run.model + ", " + (plan == "planning" ? "advancement" : plan);
      softface_tests::check_equal(label + ": failed", run.failed, 0);
      if (run.failed)
        continue;
      ++n_runs;
      const auto motion =
        softface_tests::join_and_free_motion(scene,
                                             run.displacement,
                                             planned.at(plan));
      softface_tests::check_below(label +
                                    ": join points, max |u - planned| (mm)",
                                  motion.join_error,
                                  1e-9);
      softface_tests::check_within(label + ": free points, max |u| (mm)",
                                   motion.free_largest,
                                   0.5,
                                   10.);
      const unsigned int inverted =
        n_inverted(with_free_vertex, run.displacement);
      if (run.model == "nonlinear fem")
        softface_tests::check_equal(
          label + ": inverted cells with a free vertex", inverted, 0);
      else
        softface_tests::check_within(
          label + ": inverted cells with a free vertex", inverted, 0, 1e9, 9);
      if (run.model == "nonlinear fem" || run.model == "mass tensor")
        softface_tests::check_within(label + ": max |u - u_linear fem| (mm)",
                                     run.difference.max,
                                     0.,
                                     run.model == "mass tensor" ? 1e-6 : 2.);
    }
  softface_tests::check_equal("runs that reached full load", n_runs, 8);
}

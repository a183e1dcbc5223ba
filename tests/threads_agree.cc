// Models/Threads changes the speed, not the answer. Threaded
// assembly splits the rows among the threads (RowPartition) so that every
// row sums its cells in cell order: the linear stiffness assembled on 3
// threads equals the one-thread matrix bit for bit, and every registered
// model's answer on 3 threads equals its one-thread answer (to round-off:
// deal.II splits long vectors' sums among threads, which these are not). A
// RowPartition of 7 parts visits every cell once per part its rows fall in.
// Independent truth: the one-thread computation. "3 threads" asks for 3 and
// gets as many as the machine has cores (2 here); the 7-part partition is
// checked directly.

#include <softface/core/threads.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/row_partition.h>
#include <softface/models/interface.h>

#include "scenes.h"
#include "tests.h"

using namespace softface;

SOFTFACE_TEST(threads_agree)
{
  Scene scene;
  softface_tests::make_distorted_cube_scene(scene, 4000, true);
  deallog << "cells: " << scene.triangulation.n_active_cells()
          << ", DoFs: " << scene.dof_handler.n_dofs() << std::endl;

  // The partition: each cell in exactly the parts that own one of its rows;
  // on this small mesh a third of the cells border a part (all 7: 7 visits).
  std::vector<std::array<types::global_dof_index, 12>> dofs;
  for (const auto &cell : scene.triangulation.active_cell_iterators())
    dofs.push_back(ConstrainedSystem::cell_dofs(scene, cell));
  RowPartition partition;
  partition.reinit(dofs, scene.dof_handler.n_dofs(), 7);
  long long misplaced = 0, visits = 0;
  for (unsigned int p = 0; p < partition.n_parts(); ++p)
    {
      std::vector<bool> listed(dofs.size(), false);
      for (const unsigned int c : partition.cells(p))
        listed[c] = true, ++visits;
      for (unsigned int c = 0; c < dofs.size(); ++c)
        {
          bool owns_a_row = false;
          for (const auto row : dofs[c])
            owns_a_row |= partition.owns(p, row);
          misplaced += (owns_a_row != listed[c]);
        }
    }
  softface_tests::check_equal("parts", partition.n_parts(), 7);
  softface_tests::check_equal("cells listed in a part they do not add to, "
                              "or missing from one they do",
                              misplaced,
                              0);
  softface_tests::check_below("cell visits per cell (7 parts)",
                              double(visits) / dofs.size(),
                              2.);

  SparsityPattern sparsity;
  ConstrainedSystem::make_sparsity_pattern(scene, sparsity);
  SparseMatrix<double> one, three;
  softface::Threads::set_limit(1);
  Elasticity::assemble_p1_stiffness(scene, sparsity, one);
  softface::Threads::set_limit(3);
  Elasticity::assemble_p1_stiffness(scene, sparsity, three);
  double difference = 0.;
  for (unsigned int row = 0; row < sparsity.n_rows(); ++row)
    for (auto entry = one.begin(row); entry != one.end(row); ++entry)
      difference =
        std::max(difference,
                 std::abs(entry->value() - three(row, entry->column())));
  softface_tests::check_below("stiffness, 3 threads - 1 thread, largest "
                              "entry difference (N/mm)",
                              difference,
                              0.);

  const Vector<double> turn =
    softface_tests::move_bone(scene, Point<3>(2, -1, 3), 12.);
  ParameterHandler prm;
  Models::declare_parameters(prm);
  for (const std::string &name : Models::registered_names())
    {
      Vector<double> answer[2];
      for (const unsigned int threads : {1u, 3u})
        {
          softface::Threads::set_limit(threads);
          const auto model = Models::create(name, prm);
          model->setup(scene);
          model->solve(turn, answer[threads == 3]);
        }
      softface_tests::check_below(
        name + ": 3 threads - 1 thread, relative",
        softface_tests::relative_difference(answer[1], answer[0]),
        1e-14);
    }
  softface::Threads::set_limit(1);
}

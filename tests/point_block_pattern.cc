// The linear and nonlinear FEM models make their sparsity from the points'
// neighbours and put each cell's entries straight at their places
// (PointBlockPattern). Independent truth: deal.II's pattern of
// the same layout (DoFTools::make_sparsity_pattern, through
// ConstrainedSystem), the place deal.II's SparsityPattern gives each entry,
// and the stiffness assembled by merging each cell row into deal.II's rows.
// On the generated cube (rows nearly in order) and the shared gmsh cube
// (tests/data/cube30k, irregular rows).

#include <softface/core/point_mesh.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/point_block_pattern.h>

#include "peer.h"
#include "scenes.h"
#include "tests.h"

using namespace softface;

namespace
{
  void
  compare(const std::string &name, const Scene &scene)
  {
    deallog << name << ": " << scene.triangulation.n_active_cells()
            << " cells, " << scene.dof_handler.n_dofs() << " DoFs" << std::endl;
    const PointMesh         points(scene, "test");
    const PointBlockPattern pattern(points);
    SparsityPattern         ours, dealii;
    pattern.make_sparsity(ours);
    ConstrainedSystem::make_sparsity_pattern(scene, dealii);

    // The same rows, with the same columns in the same stored order.
    long long unlike = 0;
    softface_tests::check_equal(name + ": rows",
                                ours.n_rows(),
                                dealii.n_rows());
    softface_tests::check_equal(name + ": entries",
                                ours.n_nonzero_elements(),
                                dealii.n_nonzero_elements());
    for (unsigned int row = 0; row < dealii.n_rows(); ++row)
      {
        unlike += (ours.row_length(row) != dealii.row_length(row));
        auto a = ours.begin(row);
        for (auto b = dealii.begin(row); b != dealii.end(row); ++b, ++a)
          {
            if (a == ours.end(row))
              {
                ++unlike;
                break;
              }
            unlike += (a->column() != b->column() ||
                       a->global_index() != b->global_index());
          }
      }
    softface_tests::check_equal(name + ": entries unlike deal.II's, in column "
                                       "or place",
                                unlike,
                                0);

    // Every cell's 144 places: deal.II's index of the entry.
    long long                     misplaced = 0;
    std::array<unsigned int, 144> positions;
    unsigned int                  c = 0;
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      {
        const auto dofs = ConstrainedSystem::cell_dofs(scene, cell);
        pattern.cell_positions(c++, positions.data());
        for (unsigned int r = 0; r < 12; ++r)
          for (unsigned int q = 0; q < 12; ++q)
            misplaced += (positions[12 * r + q] != dealii(dofs[r], dofs[q]));
      }
    softface_tests::check_equal(name + ": cell entries not at deal.II's "
                                       "place of the entry",
                                misplaced,
                                0);

    // The stiffness both ways: the same sums in the same order.
    SparseMatrix<double> placed, merged;
    Elasticity::assemble_p1_stiffness(scene, ours, placed, &pattern);
    Elasticity::assemble_p1_stiffness(scene, dealii, merged);
    double difference = 0., largest = 0.;
    for (unsigned int row = 0; row < dealii.n_rows(); ++row)
      for (auto entry = merged.begin(row); entry != merged.end(row); ++entry)
        {
          difference =
            std::max(difference,
                     std::abs(entry->value() - placed(row, entry->column())));
          largest = std::max(largest, std::abs(entry->value()));
        }
    softface_tests::check_below(name + ": stiffness placed - merged, "
                                       "largest entry difference (N/mm)",
                                difference,
                                0.);
    softface_tests::check_above(name + ": largest stiffness entry (N/mm)",
                                largest,
                                0.);
  }
} // namespace

SOFTFACE_TEST(point_block_pattern)
{
  Scene cube;
  softface_tests::make_distorted_cube_scene(cube, 4000, true);
  compare("distorted cube", cube);

  Scene            gmsh;
  ParameterHandler prm;
  softface_tests::read_peer_scene(prm, gmsh);
  compare("gmsh cube30k", gmsh);
}

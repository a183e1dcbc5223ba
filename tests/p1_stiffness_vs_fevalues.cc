// The closed-form P1 element stiffness
// (LinearElasticity::tetrahedron_stiffness) against deal.II's own integration:
// FEValues on FESystem(FE_SimplexP<3>(1),3) with MappingFE and QGaussSimplex,
// assembled over a whole small cube mesh. Independent truth: the textbook
// bilinear form lambda div u div v + 2 mu eps(u):eps(v) integrated by deal.II.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/full_matrix.h>

#include <softface/fe/linear_elasticity.h>
#include <softface/core/scene.h>

#include "tests.h"

using namespace softface;

SOFTFACE_TEST(p1_stiffness_vs_fevalues)
{
  Scene                scene;
  Mesh::CubeParameters cube;
  cube.target_n_tetrahedra = 400;
  Mesh::generate_cube(cube, scene.triangulation);
  // Distort the mesh so that no element is a right-angled Kuhn tetrahedron.
  GridTools::transform(
    [](const Point<3> &v) {
      return v + Point<3>(0.7 * std::sin(0.3 * v[1] + v[2]),
                          0.5 * std::cos(0.2 * v[0]),
                          0.6 * std::sin(0.1 * v[0] * v[1]));
    },
    scene.triangulation);
  scene.segments                = {{"outer", {}, {Mesh::cube_outer_face}}};
  scene.material.poissons_ratio = 0.46;
  scene.setup();
  const double lambda = scene.material.lambda(), mu = scene.material.mu();

  SparsityPattern sparsity;
  LinearElasticity::make_sparsity_pattern(scene, sparsity);
  SparseMatrix<double> closed_form(sparsity), integrated(sparsity);
  LinearElasticity::assemble_stiffness(scene, closed_form);

  const QGaussSimplex<3>               quadrature(2);
  FEValues<3>                          fe_values(scene.mapping,
                        scene.fe,
                        quadrature,
                        update_gradients | update_JxW_values);
  const FEValuesExtractors::Vector     u(0);
  FullMatrix<double>                   local(12, 12);
  std::vector<types::global_dof_index> dofs(12);
  for (const auto &cell : scene.dof_handler.active_cell_iterators())
    {
      fe_values.reinit(cell);
      local = 0;
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        for (unsigned int i = 0; i < 12; ++i)
          for (unsigned int j = 0; j < 12; ++j)
            local(i, j) +=
              (lambda * fe_values[u].divergence(i, q) *
                 fe_values[u].divergence(j, q) +
               2. * mu *
                 scalar_product(fe_values[u].symmetric_gradient(i, q),
                                fe_values[u].symmetric_gradient(j, q))) *
              fe_values.JxW(q);
      cell->get_dof_indices(dofs);
      integrated.add(dofs, local);
    }

  double max_difference = 0., max_entry = 0.;
  for (unsigned int row = 0; row < sparsity.n_rows(); ++row)
    for (auto entry = integrated.begin(row); entry != integrated.end(row);
         ++entry)
      {
        max_entry      = std::max(max_entry, std::abs(entry->value()));
        max_difference = std::max(max_difference,
                                  std::abs(entry->value() -
                                           closed_form(row, entry->column())));
      }
  deallog << "cells: " << scene.triangulation.n_active_cells()
          << ", DoFs: " << scene.dof_handler.n_dofs() << std::endl;
  softface_tests::check(max_difference <= 1e-12 * max_entry,
                        "closed form equals FEValues to 1e-12 relative");
}

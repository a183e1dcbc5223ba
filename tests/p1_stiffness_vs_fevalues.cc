// The closed-form P1 element stiffness (Elasticity::p1_stiffness, the linear
// law's tangent contracted with the shape gradients) against deal.II's own
// integration: FEValues on FESystem(FE_SimplexP<3>(1),3) with MappingFE and
// QGaussSimplex, assembled over a whole small distorted cube mesh.
// Independent truth: the textbook bilinear form lambda div u div v + 2 mu
// eps(u):eps(v) integrated by deal.II, with Lame's coefficients from the
// textbook (tests.h), not from softface's Material.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <softface/fe/constrained_system.h>
#include <softface/fe/elasticity.h>

#include "scenes.h"
#include "tests.h"
#include "textbook.h"

using namespace softface;

SOFTFACE_TEST(p1_stiffness_vs_fevalues)
{
  Scene scene;
  scene.material.poissons_ratio = 0.46;
  softface_tests::make_distorted_cube_scene(scene, 400, false);
  const auto lame =
    softface_tests::textbook_lame(scene.material.youngs_modulus(),
                                  scene.material.poissons_ratio);
  const double lambda = lame.lambda, mu = lame.mu;

  SparsityPattern sparsity;
  ConstrainedSystem::make_sparsity_pattern(scene, sparsity);
  SparseMatrix<double> closed_form, integrated(sparsity);
  Elasticity::assemble_p1_stiffness(scene, sparsity, closed_form);

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
  softface_tests::print("largest entry (N/mm)", max_entry, 4);
  softface_tests::check_below("closed form - FEValues, relative",
                              max_difference / max_entry,
                              1e-12);
}

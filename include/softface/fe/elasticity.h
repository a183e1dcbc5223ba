#ifndef softface_fe_elasticity_h
#define softface_fe_elasticity_h

#include <deal.II/base/quadrature.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>
#include <softface/core/tetrahedron.h>
#include <softface/fe/material_law.h>

#include <array>

namespace softface
{
  class PointBlockPattern;

  using namespace dealii;

  /**
   * Elasticity kernels: what a tetrahedron contributes to the nodal forces
   * and to their derivative. Two ways, one law (fe/material_law.h):
   *  - P1 in closed form: on a linear tetrahedron F = I + sum_a u_a (x)
   *    grad N_a is constant, so f_a = V P(F) grad N_a and the tangent
   *    K_ab = V grad N_a . A . grad N_b need no quadrature. The linear FEM
   *    stiffness (Mollemans et al. 2007, eqs. 6-8) is the linear law's
   *    tangent, and the mass tensor model reads its 3x3 blocks (eqs. 9-10);
   *  - by quadrature on any vector-valued element (the quadratic reference);
   *    on P1 it reproduces the closed form (a test checks that).
   */
  namespace Elasticity
  {
    /// K[a][b]: the 3x3 block coupling vertex a's force to vertex b's
    /// displacement (Cotin's K_ab^T, the paper's eq. 8).
    using CellMatrix = std::array<std::array<Tensor<2, 3>, 4>, 4>;

    /**
     * K[a][b][i][k] = V sum_JL grad_a[J] A[i][J][k][L] grad_b[L] for a
     * major-symmetric A (every hyperelastic law's), which makes the blocks
     * K[b][a] = K[a][b]^T exactly.
     */
    void
    p1_tangent(const Tetrahedron::Geometry &tetrahedron,
               const Tensor<4, 3>          &A,
               CellMatrix                  &K);

    /// A of the linear law (every law's at F = I): what the linear-elastic
    /// stiffness contracts; one per material.
    Tensor<4, 3>
    linear_tangent(const Lame &lame);

    /// The linear-elastic stiffness of a P1 tetrahedron (the paper's eq. 8),
    /// given linear_tangent() of its material.
    CellMatrix
    p1_stiffness(const Tetrahedron::Geometry &tetrahedron,
                 const Tensor<4, 3>          &linear_tangent);

    /// What one P1 tetrahedron contributes at vertex displacements u.
    struct P1Response
    {
      std::array<Tensor<1, 3>, 4> force; ///< f_a = V P grad N_a
      CellMatrix                  tangent;
    };

    /**
     * Forces and, if @p with_tangent, the tangent of a P1 tetrahedron at
     * vertex displacements @p u. Returns false if the law refuses F (det F
     * <= 0 for a nonlinear law).
     */
    bool
    p1_response(const MaterialLaw::Law             law,
                const Lame                        &lame,
                const Tetrahedron::Geometry       &tetrahedron,
                const std::array<Tensor<1, 3>, 4> &u,
                const bool                         with_tangent,
                P1Response                        &response);

    /// The unconstrained linear-elastic stiffness of the scene (P1, on the
    /// shared layout) in @p stiffness, which this reinitialises on
    /// @p sparsity (and which then refers to it: @p sparsity must outlive
    /// it). With @p pattern (@p sparsity is its sparsity) each entry goes
    /// straight to its place; otherwise each row is merged into the
    /// matrix's.
    void
    assemble_p1_stiffness(const Scene             &scene,
                          const SparsityPattern   &sparsity,
                          SparseMatrix<double>    &stiffness,
                          const PointBlockPattern *pattern = nullptr);

    /**
     * The nodal loads of the effects' body forces
     * (SceneEffects::body_force_per_unit_volume()) on @p cells, integrated
     * against the shape functions of their DoFHandler's element: added to
     * @p forces at the DoFs @p dofs holds (a rank its own DoFs, from every
     * cell at them; the serial model all), cell by cell in the order given.
     */
    void
    assemble_body_force(
      const Mapping<3>                                       &mapping,
      const Quadrature<3>                                    &quadrature,
      const SceneEffects                                     &effects,
      const std::vector<DoFHandler<3>::active_cell_iterator> &cells,
      const IndexSet                                         &dofs,
      Vector<double>                                         &forces);

    /**
     * One cell's nodal forces and, if @p K_cell is not null, its tangent, by
     * the quadrature @p fe_values was built with (reinitialised on the
     * cell); @p u_cell holds the cell's DoF values, @p component each DoF's
     * component. False if the law refuses F at a quadrature point.
     */
    bool
    cell_response(const MaterialLaw::Law           law,
                  const Lame                      &lame,
                  const FEValues<3>               &fe_values,
                  const std::vector<unsigned int> &component,
                  const std::vector<double>       &u_cell,
                  Vector<double>                  &f_cell,
                  FullMatrix<double>              *K_cell);

    /**
     * Nodal forces (and, if @p tangent is not null, the tangent, assembled
     * from zero) of the displacement @p u on any vector-valued element of
     * @p dof_handler, by quadrature, each cell with the Lame coefficients
     * tissue_lame[tissue_of_cell[c]] (tissue_lame[0] everywhere if
     * @p tissue_of_cell is empty). Returns false if the law refuses F at a
     * quadrature point, unless @p may_skip_cell marks the cell (by active
     * cell index): such a cell is then left out (a cell of prescribed DoFs
     * only, crushed by the planning). On a refusal, @p refused_cell (if not
     * null) is set to the refused cell's active cell index.
     */
    bool
    assemble(const MaterialLaw::Law            law,
             const std::vector<Lame>          &tissue_lame,
             const std::vector<unsigned char> &tissue_of_cell,
             const Mapping<3>                 &mapping,
             const DoFHandler<3>              &dof_handler,
             const Quadrature<3>              &quadrature,
             const Vector<double>             &u,
             Vector<double>                   &forces,
             SparseMatrix<double>             *tangent,
             const std::vector<bool>          *may_skip_cell = nullptr,
             unsigned int                     *refused_cell  = nullptr);
  } // namespace Elasticity
} // namespace softface

#endif

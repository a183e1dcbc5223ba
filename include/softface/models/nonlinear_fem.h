#ifndef softface_models_nonlinear_fem_h
#define softface_models_nonlinear_fem_h

#include <softface/core/tetrahedron.h>
#include <softface/fe/row_partition.h>
#include <softface/models/nonlinear_elasticity.h>

#include <array>
#include <vector>

namespace softface
{
  namespace Models
  {
    /**
     * Nonlinear FEM (Mollemans et al. 2007, Sec. 2.1, large deformation) on P1
     * tetrahedra on the shared DoF layout: St. Venant-Kirchhoff or compressible
     * Neo-Hooke (or the linear law) with the closed-form forces and tangent of
     * fe/elasticity.h, solved by the load-stepped Newton iteration of
     * NonlinearElasticity. Each tetrahedron's shape gradients, volume and
     * the positions of its 144 tangent entries in the matrix are computed
     * once per scene, so that an assembly is one pass over the cells.
     */
    class NonlinearFEM : public NonlinearElasticity
    {
    public:
      NonlinearFEM();

      static void
      declare_parameters(ParameterHandler &prm);

      /// Tissues per cell and body forces.
      unsigned int
      honoured_effects() const override;

      bool
      evaluate(const Vector<double> &u,
               Vector<double>       &forces,
               SparseMatrix<double> *tangent) const override;

      bool
      evaluate_on_ranks(const Vector<double> &u,
                        Vector<double>       &forces,
                        const bool            with_tangent) const override;

    protected:
      void
      setup_layout() override;
      void
      join_motion(const Vector<double> &prescribed,
                  Vector<double>       &motion) const override;
      void
      vertex_values(const Vector<double> &u,
                    Vector<double>       &displacement) override;

    private:
      /// Add a cell's data (below) to its arrays.
      void
      add_cell(const Tetrahedron::Geometry                   &geometry,
               const std::array<types::global_dof_index, 12> &dofs,
               const unsigned int                             tissue);

      /// Per cell: the scene's cells in serial, a rank's cells (rank_cells)
      /// on several ranks, so that a rank holds its own cells' only.
      std::vector<std::array<types::global_dof_index, 12>> cell_dofs;
      std::vector<Tetrahedron::Geometry>                   cell_geometry;
      std::vector<unsigned char>                           cell_tissue;
      std::vector<unsigned int>                            cell_entry_positions;
      /// False for cells whose every vertex is a join point: their forces
      /// act on prescribed DoFs only, so where a planning crushes them
      /// (across an osteotomy) they are left out instead of refused.
      std::vector<bool> cell_has_free_vertex;
      /// The cells by the rows they add to (threaded evaluation).
      RowPartition partition;
      /// The Lame coefficients of every tissue of the scene.
      std::vector<Lame> tissue_lame;
      /// On several MPI ranks, the cells this rank evaluates (the scene's
      /// cell numbers), its own and the ghost cells at its DoFs: the cell
      /// arrays above hold these, in this order.
      std::vector<unsigned int> rank_cells;
    };
  } // namespace Models
} // namespace softface

#endif

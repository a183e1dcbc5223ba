#ifndef softface_models_reference_fem_h
#define softface_models_reference_fem_h

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>

#include <softface/models/nonlinear_elasticity.h>

#include <array>
#include <memory>
#include <utility>
#include <vector>

namespace softface
{
  namespace Models
  {
    /**
     * The accuracy reference: the nonlinear FEM equations (or, with
     * 'Material law = linear', linear elasticity's) on quadratic tetrahedra
     * (FE_SimplexP<3>(2), forces and tangent by quadrature) on a layout of
     * the model's own, about eight times the shared layout's DoFs; solved by
     * the same load-stepped Newton iteration as 'nonlinear fem'. Converged
     * on fine meshes it is what the accuracy benchmark measures every model
     * against; with the linear law it separates linear elasticity's model
     * error from P1's discretisation error.
     *
     * A DoF is a join DoF if it lies on a bone segment's cell or boundary
     * face; it follows the segment's rigid motion, which is affine, so its
     * value is the linear interpolation of the cell's vertex values. solve()
     * returns the vertex values; displacement_field() gives the whole field.
     */
    class ReferenceFEM : public NonlinearElasticity
    {
    public:
      ReferenceFEM();

      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;

      /// The polynomial degree in code (tests).
      /// Tissues per cell and body forces.
      unsigned int
      honoured_effects() const override;

      void
      set_degree(const unsigned int degree);

      bool
      evaluate(const Vector<double> &u,
               Vector<double>       &forces,
               SparseMatrix<double> *tangent) const override;

      bool
      evaluate_on_ranks(const Vector<double> &u,
                        Vector<double>       &forces,
                        const bool            with_tangent) const override;

      /// The whole field after solve().
      std::pair<const DoFHandler<3> *, const Vector<double> *>
      displacement_field() const override;

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
      unsigned int degree = 2;

      std::unique_ptr<FESystem<3>>   fe;
      std::unique_ptr<DoFHandler<3>> dof_handler;
      /// The DoF at each vertex DoF of the shared layout.
      std::vector<types::global_dof_index> at_vertex_dof;
      Vector<double>                       solution;
      /// Cells all of whose DoFs are join DoFs (see NonlinearFEM).
      std::vector<bool> all_join_cell;
      std::vector<Lame> tissue_lame;
      Vector<double>    layout_body_force;

      /// On several MPI ranks: the model's DoFs on the layout's
      /// triangulation, the cells this rank evaluates (its own and the
      /// ghost cells at its DoFs) and their DoFs in the serial layout.
      std::unique_ptr<DoFHandler<3>>                   ranks_dofs;
      std::vector<DoFHandler<3>::active_cell_iterator> rank_cells;
      std::vector<types::global_dof_index>             rank_cell_serial_dofs;
      /// Build them (setup_layout() on several ranks).
      void
      setup_ranks();
    };
  } // namespace Models
} // namespace softface

#endif

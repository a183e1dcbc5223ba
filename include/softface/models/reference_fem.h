#ifndef softface_models_reference_fem_h
#define softface_models_reference_fem_h

#include <deal.II/base/index_set.h>
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
     * returns the vertex values; displacement_field() gives the whole field
     * (displacement_field_at() on several MPI ranks, where the model's DoFs
     * live on the ranks' parts of the mesh).
     */
    class ReferenceFEM : public NonlinearElasticity
    {
    public:
      ReferenceFEM();

      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm) override;

      /// Tissues per cell and body forces.
      unsigned int
      honoured_effects() const override;

      /// The polynomial degree in code (tests).
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

      /// The whole field after a solve() that ran whole (on one rank, or
      /// where why_not_on_ranks() says so).
      std::pair<const DoFHandler<3> *, const Vector<double> *>
      displacement_field() const override;

      /// The field at points after a solve() on the ranks.
      bool
      displacement_field_at(const std::vector<Point<3>>     &points,
                            const std::vector<unsigned int> &cells,
                            const std::vector<Point<3>>     &reference_points,
                            std::vector<Tensor<1, 3>> &values) const override;

    protected:
      void
      setup_layout() override;
      void
      join_motion(const Vector<double> &prescribed,
                  Vector<double>       &motion) const override;
      void
      vertex_values(const Vector<double> &u,
                    Vector<double>       &displacement) override;
      const Vector<double> *
      guess_in_model_numbering(const Vector<double> *guess,
                               Vector<double>       &translated) const override;
      /// NonlinearElasticity's, with has_solution false until it succeeds.
      void
      do_solve(const Vector<double> &prescribed,
               Vector<double>       &displacement) override;

    private:
      unsigned int degree = 2;

      std::unique_ptr<FESystem<3>> fe;
      std::vector<Lame>            tissue_lame;
      /// Whether the last solve() succeeded, on every rank alike.
      bool           has_solution = false;
      Vector<double> layout_body_force;

      /// Where it runs whole: the element's DoFs on the scene's mesh, the
      /// DoF at each vertex DoF of the shared layout, the cells all of whose
      /// DoFs are join DoFs (see NonlinearFEM), and the last solution.
      std::unique_ptr<DoFHandler<3>>       dof_handler;
      std::vector<types::global_dof_index> at_vertex_dof;
      std::vector<bool>                    all_join_cell;
      Vector<double>                       solution;
      /// Build them.
      void
      setup_serial();

      /**
       * On several MPI ranks: the element's DoFs on the layout's
       * triangulation, which number the model's whole vectors (nothing of
       * the scene's cells is read, so the members of a group of ranks may
       * hold none); the cells this rank evaluates (its own and the ghost
       * cells at its DoFs), their DoFs and whether all of them are join
       * DoFs; the shared layout's DoF (serial) of each vertex DoF this
       * rank owns; and the last solution at the locally relevant DoFs.
       */
      std::unique_ptr<DoFHandler<3>>                   ranks_dofs;
      std::vector<DoFHandler<3>::active_cell_iterator> rank_cells;
      std::vector<types::global_dof_index>             rank_cell_dofs;
      std::vector<bool>                                rank_cell_all_join;
      std::vector<std::pair<types::global_dof_index, types::global_dof_index>>
                          rank_vertex_dofs;
      IndexSet            relevant_dofs;
      std::vector<double> relevant_solution;
      /// Build them.
      void
      setup_ranks();
      /// The cells this rank evaluates, their DoFs, the DoFs' points and
      /// components, the owned vertex DoFs' layout DoFs; returns the join
      /// flags this rank decides (for its own DoFs; others' are not final).
      std::vector<unsigned char>
      collect_rank_cells();
      /// Each rank's join flags for its own DoFs into is_join on every
      /// rank (@p join released), and the centroid of the DoFs' points.
      /// Collective.
      void
      share_join_flags(std::vector<unsigned char> &join);
      /// The body force against this element on the layout (each rank its
      /// own DoFs', summed). Collective.
      void
      assemble_body_force_on_ranks();
      /// Each rank's part of @p whole (zero elsewhere) summed over the
      /// ranks, on every rank. Collective.
      void
      sum_over_ranks(Vector<double> &whole) const;
    };
  } // namespace Models
} // namespace softface

#endif

// The reference model (models): the nonlinear FEM equations on quadratic
// tetrahedra on a layout of its own, by quadrature; the accuracy benchmark's
// converged answer. The Newton solve is NonlinearElasticity's.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <softface/fe/elasticity.h>
#include <softface/models/reference_fem.h>

#include <array>
#include <set>

namespace softface
{
  namespace Models
  {
    namespace
    {
      // The weights of a tetrahedron's four vertices at the point xi of the
      // unit cell (its barycentric coordinates).
      std::array<double, 4>
      vertex_weights(const Point<3> &xi)
      {
        return {{1. - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]}};
      }
    } // namespace

    ReferenceFEM::ReferenceFEM()
        : NonlinearElasticity("reference fem")
    {}

    void
    ReferenceFEM::declare_parameters(ParameterHandler &prm)
    {
      NonlinearElasticity::declare_parameters(prm);
      prm.declare_entry("Polynomial degree",
                        "2",
                        Patterns::Integer(1, 2),
                        "Degree of the tetrahedra: 2 (quadratic, the "
                        "reference) or 1 (the nonlinear FEM model's "
                        "discretisation, here by quadrature: a cross-check).");
    }

    void
    ReferenceFEM::parse_parameters(ParameterHandler &prm)
    {
      NonlinearElasticity::parse_parameters(prm);
      degree = prm.get_integer("Polynomial degree");
    }

    unsigned int
    ReferenceFEM::honoured_effects() const
    {
      return SceneEffects::cell_materials | SceneEffects::body_forces;
    }

    void
    ReferenceFEM::set_degree(const unsigned int d)
    {
      degree = d;
    }

    void
    ReferenceFEM::setup_layout()
    {
      const auto timed = phase("layout");
      fe          = std::make_unique<FESystem<3>>(FE_SimplexP<3>(degree), 3);
      dof_handler = std::make_unique<DoFHandler<3>>(scene->triangulation);
      dof_handler->distribute_dofs(*fe);
      const unsigned int n = dof_handler->n_dofs();

      // Join DoFs: every DoF of a segment's cell and of its boundary faces,
      // and the DoFs at join vertices. The support points serve ML's
      // rigid-body modes.
      const auto        &unit_points = fe->get_unit_support_points();
      const unsigned int n_cell      = fe->n_dofs_per_cell();
      is_join.assign(n, false);
      at_vertex_dof.assign(scene->dof_handler.n_dofs(),
                           numbers::invalid_dof_index);
      dof_points.resize(n);
      dof_component.resize(n);
      std::vector<types::global_dof_index> dofs(n_cell), face_dofs;
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          bool bone_cell = false;
          for (const auto &segment : scene->segments)
            bone_cell |= segment.material_ids.count(cell->material_id()) > 0;
          for (unsigned int i = 0; i < n_cell; ++i)
            {
              const unsigned int c  = fe->system_to_component_index(i).first;
              const Point<3>    &xi = unit_points[i];
              const std::array<double, 4> weight = vertex_weights(xi);
              Point<3>                    x;
              for (unsigned int a = 0; a < 4; ++a)
                {
                  const auto vertex_dof =
                    scene->vertex_dofs()[cell->vertex_index(a)][c];
                  x += weight[a] * cell->vertex(a);
                  if (weight[a] == 1.)
                    {
                      at_vertex_dof[vertex_dof] = dofs[i];
                      if (scene->join_dofs()[vertex_dof])
                        is_join[dofs[i]] = true;
                    }
                }
              dof_points[dofs[i]]    = x;
              dof_component[dofs[i]] = c;
              if (bone_cell)
                is_join[dofs[i]] = true;
            }
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              for (const auto &segment : scene->segments)
                if (segment.boundary_ids.count(cell->face(f)->boundary_id()))
                  {
                    face_dofs.resize(fe->n_dofs_per_face(f));
                    cell->face(f)->get_dof_indices(face_dofs);
                    for (const auto i : face_dofs)
                      is_join[i] = true;
                  }
        }

      // A cell whose four vertices are join points of two or more segments
      // (across the kerf of an osteotomy, between the teeth) is carried by
      // the bones whole, as on the P1 layout: its edge and face DoFs follow
      // the vertices too. Otherwise it keeps free mid-edge DoFs but no
      // freedom to avoid the shape the bones' relative motion forces on it,
      // and the solve stops where the planning crushes it, which the P1
      // models pass. A cell on one segment only moves with it rigidly and
      // keeps its free DoFs.
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          std::set<unsigned int> segments_of_vertices;
          bool                   vertices_join = true;
          for (const unsigned int a : cell->vertex_indices())
            {
              const unsigned int v = cell->vertex_index(a);
              vertices_join &= scene->join_dofs()[scene->vertex_dofs()[v][0]];
              segments_of_vertices.insert(scene->vertex_segment()[v]);
            }
          if (!vertices_join || segments_of_vertices.size() < 2)
            continue;
          cell->get_dof_indices(dofs);
          for (const auto i : dofs)
            is_join[i] = true;
        }

      all_join_cell.assign(scene->triangulation.n_active_cells(), false);
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          bool all = true;
          for (const auto i : dofs)
            all &= is_join[i];
          all_join_cell[cell->active_cell_index()] = all;
        }

      add_detail("degree", degree);
      rank_cells.clear();
      rank_cell_serial_dofs.clear();
      ranks_dofs.reset();
      if (Utilities::MPI::n_mpi_processes(communicator) > 1 &&
          why_not_on_ranks().empty())
        setup_ranks();
      else
        {
          DynamicSparsityPattern dsp(n, n);
          DoFTools::make_sparsity_pattern(*dof_handler, dsp);
          sparsity.copy_from(dsp);
        }

      // The effects: each tissue's Lame coefficients, and the body force
      // integrated against this layout's shape functions.
      tissue_lame.clear();
      for (unsigned int t = 0; t < scene->n_tissues(); ++t)
        tissue_lame.push_back(scene->tissue(t).lame());
      if (scene->has_body_force())
        {
          Elasticity::assemble_body_force(scene->mapping,
                                          *dof_handler,
                                          QGaussSimplex<3>(3),
                                          scene->effects.cell_body_force,
                                          layout_body_force);
          body_force = &layout_body_force;
        }
    }

    void
    ReferenceFEM::setup_ranks()
    {
      ranks_layout = &distributed_layout(*scene);
      ranks_dofs = std::make_unique<DoFHandler<3>>(ranks_layout->triangulation);
      ranks_dofs->distribute_dofs(*fe);
      ranks_dof_handler = ranks_dofs.get();
      IndexSet relevant;
      DoFTools::extract_locally_relevant_dofs(*ranks_dofs, relevant);
      const IndexSet &owned = ranks_dofs->locally_owned_dofs();
      ranks_serial_dofs.assign(relevant.n_elements(),
                               numbers::invalid_dof_index);
      ranks_dofs_per_cell = fe->n_dofs_per_cell();
      ranks_cell_dofs.clear();

      // A cell of the layout is the scene's cell with the same vertices in
      // the same order (DistributedLayout::serial_cell()), and a quadratic
      // element has one DoF per edge and component: the same local DoF is
      // the same DoF. Checked by the DoFs' support points.
      const auto        &unit_points = fe->get_unit_support_points();
      const unsigned int n           = ranks_dofs_per_cell;
      std::vector<types::global_dof_index> dofs(n), serial_dofs(n);
      for (const auto &cell : ranks_dofs->active_cell_iterators())
        if (!cell->is_artificial())
          {
            const auto serial = ranks_layout->serial_cell(cell);
            const DoFHandler<3>::active_cell_iterator serial_cell(
              &scene->triangulation,
              serial->level(),
              serial->index(),
              dof_handler.get());
            cell->get_dof_indices(dofs);
            serial_cell->get_dof_indices(serial_dofs);
            bool at_own_dof = false;
            for (unsigned int i = 0; i < n; ++i)
              {
                const Point<3> &xi = unit_points[i];
                Point<3> x = (1. - xi[0] - xi[1] - xi[2]) * cell->vertex(0);
                for (unsigned int a = 1; a < 4; ++a)
                  x += xi[a - 1] * cell->vertex(a);
                AssertThrow(x.distance(dof_points[serial_dofs[i]]) <=
                              1e-9 * (1. + x.norm()),
                            ExcInternalError());
                ranks_serial_dofs[relevant.index_within_set(dofs[i])] =
                  serial_dofs[i];
                at_own_dof |= owned.is_element(dofs[i]);
              }
            if (!at_own_dof)
              continue;
            rank_cells.push_back(cell);
            ranks_cell_dofs.insert(ranks_cell_dofs.end(),
                                   dofs.begin(),
                                   dofs.end());
            rank_cell_serial_dofs.insert(rank_cell_serial_dofs.end(),
                                         serial_dofs.begin(),
                                         serial_dofs.end());
          }
    }

    bool
    ReferenceFEM::evaluate_on_ranks(const Vector<double> &u,
                                    Vector<double>       &forces,
                                    const bool            with_tangent) const
    {
      distributed_tangent->begin_assembly(with_tangent);
      // The serial evaluation's rule (evaluate()).
      FEValues<3>               fe_values(scene->mapping,
                            *fe,
                            QGaussSimplex<3>(3),
                            update_gradients | update_JxW_values);
      const unsigned int        n = fe->n_dofs_per_cell();
      std::vector<unsigned int> component(n);
      for (unsigned int i = 0; i < n; ++i)
        component[i] = fe->system_to_component_index(i).first;
      std::vector<double> u_cell(n);
      Vector<double>      f_cell(n);
      FullMatrix<double>  K_cell(n, n);
      const auto         &tissue_of_cell = scene->effects.tissue_of_cell;
      // The first refused cell in the scene's order, as on one rank.
      unsigned int refused = numbers::invalid_unsigned_int;
      for (unsigned int k = 0; k < rank_cells.size(); ++k)
        {
          const auto        &cell = rank_cells[k];
          const unsigned int c    = DistributedLayout::serial_cell_index(cell);
          fe_values.reinit(cell);
          for (unsigned int i = 0; i < n; ++i)
            u_cell[i] = u[rank_cell_serial_dofs[n * k + i]];
          const Lame &lame =
            tissue_lame[tissue_of_cell.empty() ? 0 : tissue_of_cell[c]];
          if (Elasticity::cell_response(law,
                                        lame,
                                        fe_values,
                                        component,
                                        u_cell,
                                        f_cell,
                                        with_tangent ? &K_cell : nullptr))
            distributed_tangent->add_cell(k, f_cell, K_cell);
          else if (!all_join_cell[c])
            refused = std::min(refused, c);
        }
      return end_evaluation_on_ranks(forces, refused);
    }

    bool
    ReferenceFEM::evaluate(const Vector<double> &u,
                           Vector<double>       &forces,
                           SparseMatrix<double> *tangent) const
    {
      AssertThrow(!distributed_tangent,
                  ExcMessage("On several MPI ranks the model evaluates "
                             "through evaluate_on_ranks()."));
      // A 3-point-per-direction rule: exact for the quadratic element's
      // linear stiffness and accurate for its nonlinear terms.
      unsigned int refused_cell = 0;
      const bool   valid        = Elasticity::assemble(law,
                                              tissue_lame,
                                              scene->effects.tissue_of_cell,
                                              scene->mapping,
                                              *dof_handler,
                                              QGaussSimplex<3>(3),
                                              u,
                                              forces,
                                              tangent,
                                              &all_join_cell,
                                              &refused_cell);
      if (!valid)
        refusal = describe_cell(refused_cell);
      return valid;
    }

    void
    ReferenceFEM::join_motion(const Vector<double> &prescribed,
                              Vector<double>       &motion) const
    {
      // A join DoF's value is the linear interpolation of its cell's vertex
      // values (the rigid motion is affine), found cell by cell: kept per
      // DoF it took 64 bytes of every DoF on every rank.
      motion.reinit(is_join.size());
      const auto        &unit_points = fe->get_unit_support_points();
      const unsigned int n_cell      = fe->n_dofs_per_cell();
      std::vector<types::global_dof_index> dofs(n_cell);
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < n_cell; ++i)
            if (is_join[dofs[i]])
              {
                const unsigned int c  = fe->system_to_component_index(i).first;
                const Point<3>    &xi = unit_points[i];
                const std::array<double, 4> weight = vertex_weights(xi);
                double                      value  = 0.;
                for (unsigned int a = 0; a < 4; ++a)
                  value +=
                    weight[a] *
                    prescribed[scene->vertex_dofs()[cell->vertex_index(a)][c]];
                motion[dofs[i]] = value;
              }
        }
    }

    void
    ReferenceFEM::vertex_values(const Vector<double> &u,
                                Vector<double>       &displacement)
    {
      solution = u;
      displacement.reinit(scene->dof_handler.n_dofs());
      for (unsigned int i = 0; i < displacement.size(); ++i)
        if (at_vertex_dof[i] != numbers::invalid_dof_index)
          displacement[i] = u[at_vertex_dof[i]];
    }

    std::pair<const DoFHandler<3> *, const Vector<double> *>
    ReferenceFEM::displacement_field() const
    {
      if (solution.size() > 0)
        return {dof_handler.get(), &solution};
      return {nullptr, nullptr};
    }

    SOFTFACE_REGISTER_MODEL(ReferenceFEM,
                            "reference fem",
                            "The nonlinear FEM equations on quadratic "
                            "tetrahedra (by quadrature, on a layout of its "
                            "own): the accuracy benchmark's reference.")
  } // namespace Models
} // namespace softface

// The nonlinear FEM model (models; Mollemans et al. 2007, Sec. 2.1) on P1
// tetrahedra and the shared layout: its discretisation (cell geometry,
// closed-form forces and tangent added straight into the matrix); the Newton
// solve is NonlinearElasticity's.

#include <softface/core/point_mesh.h>
#include <softface/core/release.h>
#include <softface/core/threads.h>
#include <softface/fe/constrained_system.h>
#include <softface/fe/elasticity.h>
#include <softface/fe/point_block_pattern.h>
#include <softface/models/nonlinear_fem.h>

#include <algorithm>


namespace softface
{
  namespace Models
  {
    NonlinearFEM::NonlinearFEM()
        : NonlinearElasticity("nonlinear fem")
    {}

    void
    NonlinearFEM::declare_parameters(ParameterHandler &prm)
    {
      NonlinearElasticity::declare_parameters(prm);
    }

    unsigned int
    NonlinearFEM::honoured_effects() const
    {
      return SceneEffects::cell_materials | SceneEffects::body_forces |
             SceneEffects::free_vertex_constraints;
    }

    void
    NonlinearFEM::add_cell(const Tetrahedron::Geometry &geometry,
                           const std::array<types::global_dof_index, 12> &dofs,
                           const unsigned int tissue)
    {
      cell_geometry.push_back(geometry);
      cell_dofs.push_back(dofs);
      cell_tissue.push_back(tissue);
      bool free = false;
      for (const auto dof : dofs)
        free |= !is_join[dof];
      cell_has_free_vertex.push_back(free);
    }

    void
    NonlinearFEM::setup_layout()
    {
      is_join = scene->join_dofs();
      tissue_lame.clear();
      for (unsigned int t = 0; t < scene->n_tissues(); ++t)
        tissue_lame.push_back(scene->tissue(t).lame());
      body_force =
        scene->has_body_force() ? &scene->effects.body_force : nullptr;
      vertex_constraints.reset();
      if (scene->has_vertex_constraints())
        vertex_constraints = std::make_unique<VertexConstraintSet>(*scene);
      cell_dofs.clear();
      cell_geometry.clear();
      cell_tissue.clear();
      cell_has_free_vertex.clear();
      rank_cells.clear();

      // On several MPI ranks each evaluates its own cells into a
      // distributed tangent, from its part of the mesh (the same vertices
      // in the same order as the scene's cells: the same numbers); the
      // serial matrix's positions are not needed.
      if (Utilities::MPI::n_mpi_processes(communicator) > 1 &&
          why_not_on_ranks().empty())
        {
          std::vector<DoFHandler<3>::active_cell_iterator> cells;
          {
            const auto timed = phase("partition");
            ranks_layout     = &distributed_layout(*scene);
            release(cell_entry_positions);
            ranks_dof_handler = &ranks_layout->dof_handler;
            ranks_serial_dofs.clear();
            for (const auto dof : ranks_layout->locally_relevant_dofs)
              ranks_serial_dofs.push_back(ranks_layout->serial_dof(dof));
            // Its own cells and the ghost cells at its DoFs: each rank adds
            // its own rows only (DistributedTangent::set_cells()).
            ranks_dofs_per_cell = 12;
            ranks_layout->cells_at_owned_dofs(cells, ranks_cell_dofs);
          }
          const auto timed = phase("cell geometry");
          for (unsigned int k = 0; k < cells.size(); ++k)
            {
              std::array<types::global_dof_index, 12> dofs;
              for (unsigned int i = 0; i < 12; ++i)
                dofs[i] = ranks_layout->serial_dof(ranks_cell_dofs[12 * k + i]);
              add_cell(Tetrahedron::geometry(Tetrahedron::vertices(cells[k])),
                       dofs,
                       ranks_layout->tissue_of_cell(cells[k]));
              rank_cells.push_back(
                DistributedLayout::serial_cell_index(cells[k]));
            }
          return;
        }

      {
        const auto timed = phase("cell geometry");
        for (const auto &cell : scene->triangulation.active_cell_iterators())
          add_cell(Tetrahedron::geometry(Tetrahedron::vertices(cell)),
                   ConstrainedSystem::cell_dofs(*scene, cell),
                   scene->tissue_of_cell(cell->active_cell_index()));
      }

      const auto timed = phase("matrix positions");
      partition.reinit(cell_dofs, is_join.size(), Threads::n_threads());
      // Where each of a cell's 144 tangent entries lives in the matrix's
      // value array: every Newton iteration adds to them directly instead of
      // searching the rows (which took most of the assembly time). Without
      // vertex constraints (whose fill joins a slit's sides) from the
      // points' neighbours (PointBlockPattern), else by a merge along each
      // row of deal.II's pattern.
      cell_entry_positions.resize(144 * cell_dofs.size());
      if (!scene->has_vertex_constraints() && scene->dofs_are_point_blocks())
        {
          const PointMesh         points(*scene, model_name);
          const PointBlockPattern pattern(points);
          pattern.make_sparsity(sparsity);
          for (unsigned int c = 0; c < cell_dofs.size(); ++c)
            pattern.cell_positions(c, &cell_entry_positions[144 * c]);
          return;
        }
      ConstrainedSystem::make_sparsity_pattern(*scene, sparsity);
      for (unsigned int c = 0; c < cell_dofs.size(); ++c)
        {
          const auto &dofs  = cell_dofs[c];
          const auto  order = ConstrainedSystem::sorted_order(dofs);
          for (unsigned int r = 0; r < 12; ++r)
            {
              // A square pattern stores the diagonal first, then the other
              // columns ascending: one merge along the row finds all twelve.
              const auto row      = dofs[r];
              auto       entry    = sparsity.begin(row);
              const auto diagonal = entry->global_index();
              ++entry;
              for (const unsigned int q : order)
                {
                  if (dofs[q] == row)
                    {
                      cell_entry_positions[144 * c + 12 * r + q] = diagonal;
                      continue;
                    }
                  while (entry->column() < dofs[q])
                    ++entry;
                  Assert(entry->column() == dofs[q], ExcInternalError());
                  cell_entry_positions[144 * c + 12 * r + q] =
                    entry->global_index();
                }
            }
        }
    }

    bool
    NonlinearFEM::evaluate(const Vector<double> &u,
                           Vector<double>       &forces,
                           SparseMatrix<double> *tangent) const
    {
      AssertThrow(!distributed_tangent,
                  ExcMessage("On several MPI ranks the model evaluates "
                             "through evaluate_on_ranks()."));
      forces.reinit(u.size());
      double *values = nullptr;
      if (tangent != nullptr)
        {
          Assert(&tangent->get_sparsity_pattern() == &sparsity,
                 ExcMessage("The tangent must live on sparsity_pattern()."));
          *tangent = 0;
          // SparseMatrix keeps its values in one array in the order of the
          // sparsity pattern's entries; a square matrix stores the diagonal
          // first in each row, so entry (0,0) is the start of that array.
          values = &tangent->diag_element(0);
        }
      // Each part adds its own rows (RowPartition); a refusal is the first
      // refused cell in cell order, as on one thread.
      const unsigned int        n_parts = partition.n_parts();
      std::vector<unsigned int> refused(n_parts, numbers::invalid_unsigned_int);
      Threads::run_tasks(n_parts, [&](const unsigned int p) {
        Elasticity::P1Response      response;
        std::array<Tensor<1, 3>, 4> u_cell;
        const auto                  first = partition.first_row_of(p);
        const auto                  end   = partition.first_row_of(p + 1);
        for (const unsigned int c : partition.cells(p))
          {
            const auto &dofs = cell_dofs[c];
            for (unsigned int a = 0; a < 4; ++a)
              for (unsigned int i = 0; i < 3; ++i)
                u_cell[a][i] = u[dofs[3 * a + i]];
            if (!Elasticity::p1_response(law,
                                         tissue_lame[cell_tissue[c]],
                                         cell_geometry[c],
                                         u_cell,
                                         values != nullptr,
                                         response))
              {
                // A cell of join points only acts on prescribed DoFs: a
                // planning that crushes it (across an osteotomy's kerf) is
                // not the tissue's doing, and it is left out.
                if (!cell_has_free_vertex[c])
                  continue;
                refused[p] = c;
                return;
              }
            for (unsigned int r = 0; r < 12; ++r)
              {
                const auto row = dofs[r];
                if (row < first || row >= end)
                  continue;
                forces[row] += response.force[r / 3][r % 3];
                if (values == nullptr)
                  continue;
                const unsigned int *position =
                  &cell_entry_positions[144 * c + 12 * r];
                for (unsigned int b = 0; b < 4; ++b)
                  for (unsigned int j = 0; j < 3; ++j)
                    values[*position++] += response.tangent[r / 3][b][r % 3][j];
              }
          }
      });
      const unsigned int first_refused =
        *std::min_element(refused.begin(), refused.end());
      if (first_refused != numbers::invalid_unsigned_int)
        {
          refusal = describe_cell(first_refused);
          return false;
        }
      return true;
    }

    bool
    NonlinearFEM::evaluate_on_ranks(const Vector<double> &u,
                                    Vector<double>       &forces,
                                    const bool            with_tangent) const
    {
      distributed_tangent->begin_assembly(with_tangent);
      Elasticity::P1Response      response;
      std::array<Tensor<1, 3>, 4> u_cell;
      // The first refused cell in the scene's order, as on one rank.
      unsigned int refused = numbers::invalid_unsigned_int;
      for (unsigned int k = 0; k < rank_cells.size(); ++k)
        {
          const auto &serial_dofs = cell_dofs[k];
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              u_cell[a][i] = u[serial_dofs[3 * a + i]];
          if (Elasticity::p1_response(law,
                                      tissue_lame[cell_tissue[k]],
                                      cell_geometry[k],
                                      u_cell,
                                      with_tangent,
                                      response))
            distributed_tangent->add_cell(k, response);
          else if (cell_has_free_vertex[k])
            refused = std::min(refused, rank_cells[k]);
        }
      return end_evaluation_on_ranks(forces, refused);
    }

    void
    NonlinearFEM::join_motion(const Vector<double> &prescribed,
                              Vector<double>       &motion) const
    {
      motion.reinit(is_join.size());
      for (unsigned int i = 0; i < is_join.size(); ++i)
        if (is_join[i])
          motion[i] = prescribed[i];
    }

    void
    NonlinearFEM::vertex_values(const Vector<double> &u,
                                Vector<double>       &displacement)
    {
      displacement = u;
    }

    SOFTFACE_REGISTER_MODEL(NonlinearFEM,
                            "nonlinear fem",
                            "Large-deformation elasticity on P1 tetrahedra "
                            "(St. Venant-Kirchhoff or Neo-Hooke), Newton with "
                            "line search and load-step cut-back.")
  } // namespace Models
} // namespace softface

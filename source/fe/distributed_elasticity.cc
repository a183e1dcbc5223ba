// Linear elasticity on several MPI ranks: the
// linear FEM model's stiffness assembled on each rank's rows from the cells
// at them (OwnedRowsMatrix) without the join DoFs' couplings, the right-hand
// side from the cells at join DoFs (AffineConstraints), CG with the serial
// model's ML. See fe/distributed_elasticity.h.

#include <deal.II/base/index_set.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <softface/core/error.h>
#include <softface/core/release.h>
#include <softface/core/tetrahedron.h>
#include <softface/fe/distributed_elasticity.h>
#include <softface/fe/elasticity.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <cmath>
#include <sstream>

namespace softface
{
  namespace DistributedElasticity
  {
    namespace
    {
      // The cell's stiffness from its vertices (the scene's cell's, in the
      // same order: the serial model's element matrix, bit for bit) and its
      // tissue; rows and columns in the order vertex, component, as @p dofs.
      void
      cell_stiffness(const DistributedLayout                   &layout,
                     const std::vector<Tensor<4, 3>>           &A,
                     const DoFHandler<3>::active_cell_iterator &cell,
                     FullMatrix<double>                        &cell_matrix,
                     std::vector<types::global_dof_index>      &dofs)
      {
        const auto K = Elasticity::p1_stiffness(Tetrahedron::geometry(
                                                  Tetrahedron::vertices(cell)),
                                                A[layout.tissue_of_cell(cell)]);
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int i = 0; i < 3; ++i)
            {
              dofs[3 * a + i] = cell->vertex_dof_index(a, i);
              for (unsigned int b = 0; b < 4; ++b)
                for (unsigned int k = 0; k < 3; ++k)
                  cell_matrix(3 * a + i, 3 * b + k) = K[a][b][i][k];
            }
      }

      std::vector<Tensor<4, 3>>
      tangents(const Scene &scene)
      {
        std::vector<Tensor<4, 3>> A;
        for (unsigned int t = 0; t < scene.n_tissues(); ++t)
          A.push_back(Elasticity::linear_tangent(scene.tissue(t).lame()));
        return A;
      }
    } // namespace

    void
    LinearSystem::assemble(const DistributedLayout        &layout_in,
                           const LinearSolver::Parameters &parameters_in)
    {
      layout                = &layout_in;
      parameters            = parameters_in;
      const Scene    &scene = layout->scene;
      const MPI_Comm  comm  = layout->communicator;
      const IndexSet &owned = layout->locally_owned_dofs;
      // Every rank holds the scene's vertex constraints (a member without
      // its cells too), so every rank refuses alike.
      if (scene.has_vertex_constraints())
        throw Error("Linear elasticity on several MPI ranks does not honour "
                    "vertex constraints (sliding contact, separated lips); "
                    "run this scene on one rank.");
      if (parameters.method != "cg amg")
        throw Error("Linear elasticity on several MPI ranks solves with 'cg "
                    "amg' only, not '" +
                    parameters.method + "'.");

      // The join DoFs' rows and columns leave the matrix (their values, the
      // planning's, enter each solve's right-hand side).
      join_rows.clear();
      join_rows.reinit(layout->locally_relevant_dofs);
      for (const auto dof : layout->locally_relevant_dofs)
        if (layout->is_join_dof(dof))
          join_rows.add_line(dof);
      join_rows.close();

      // Every cell at a DoF this rank owns, its own and ghost cells: each
      // adds to this rank's rows only (OwnedRowsMatrix).
      std::vector<char> relevant_is_join;
      relevant_is_join.reserve(layout->locally_relevant_dofs.n_elements());
      for (const auto dof : layout->locally_relevant_dofs)
        relevant_is_join.push_back(join_rows.is_constrained(dof));
      stiffness = std::make_unique<OwnedRowsMatrix>(
        owned,
        layout->locally_relevant_dofs,
        relevant_is_join,
        OwnedRowsMatrix::JoinCouplings::dropped,
        comm);
      std::vector<DoFHandler<3>::active_cell_iterator> cells;
      std::vector<types::global_dof_index>             cell_dofs;
      layout->cells_at_owned_dofs(cells, cell_dofs);
      stiffness->set_cells(cell_dofs, 12);
      release(cell_dofs);

      const auto                           A = tangents(scene);
      FullMatrix<double>                   cell_matrix(12, 12);
      std::vector<types::global_dof_index> dofs(12);
      for (unsigned int k = 0; k < cells.size(); ++k)
        {
          cell_stiffness(*layout, A, cells[k], cell_matrix, dofs);
          for (unsigned int i = 0; i < 12; ++i)
            if (stiffness->row(k, i) >= 0)
              stiffness->add_row(k, i, [&](const unsigned int q) {
                return cell_matrix(i, q);
              });
        }
      // The join rows' diagonal, for the serial model's right-hand side
      // norm (solve()).
      join_diagonal = stiffness->eliminate_join_dofs();
      // Assembled once: the cells' places are not needed again, and ML's
      // setup (the run's peak) comes next.
      stiffness->release_cells();
      amg.reset();
    }

    void
    LinearSystem::build_preconditioner()
    {
      Assert(layout != nullptr, ExcMessage("LinearSystem::assemble() first."));
      const MPI_Comm  comm  = layout->communicator;
      const IndexSet &owned = layout->locally_owned_dofs;
      // ML as the serial model builds it: the owned DoFs' points and
      // components, rotations about the centroid of all vertices.
      std::vector<Point<3>>     points(owned.n_elements());
      std::vector<unsigned int> component(owned.n_elements(),
                                          numbers::invalid_unsigned_int);
      for (const auto &cell : layout->dof_handler.active_cell_iterators())
        if (!cell->is_artificial())
          for (const unsigned int v : cell->vertex_indices())
            for (unsigned int c = 0; c < 3; ++c)
              {
                const auto dof = cell->vertex_dof_index(v, c);
                if (owned.is_element(dof))
                  {
                    points[owned.index_within_set(dof)]    = cell->vertex(v);
                    component[owned.index_within_set(dof)] = c;
                  }
              }
      Point<3> centroid;
      for (const auto &p : points)
        centroid += p;
      centroid = Point<3>(
        Utilities::MPI::sum(static_cast<const Tensor<1, 3> &>(centroid), comm));
      centroid /=
        std::max<types::global_dof_index>(layout->dof_handler.n_dofs(), 1);
      Teuchos::ParameterList list;
      const auto             null_space = LinearSolver::amg_parameters(
        parameters, stiffness->matrix(), points, component, centroid, list);
      amg = std::make_unique<TrilinosWrappers::PreconditionAMG>();
      amg->initialize(stiffness->matrix(), list);
    }

    bool
    cg(const TrilinosWrappers::SparseMatrix    &matrix,
       const TrilinosWrappers::PreconditionAMG &amg,
       const TrilinosWrappers::MPI::Vector     &rhs,
       TrilinosWrappers::MPI::Vector           &solution,
       const double                             tolerance,
       const unsigned int                       limit,
       LinearSolver::Result                    &result)
    {
      SolverControl                           control(limit,
                            tolerance,
                            /*log_history=*/false,
                            /*log_result=*/false);
      SolverCG<TrilinosWrappers::MPI::Vector> solver(control);
      // As the serial solver does: a step length alpha <= 0 means
      // p^T K p <= 0 (K not positive definite); alpha is a global value, so
      // every rank stops at the same iteration.
      solver.connect_coefficients_slot([&](const double alpha, const double) {
        if (!(alpha > 0.))
          result.negative_curvature = true;
      });
      solver.connect([&](const unsigned int,
                         const double,
                         const TrilinosWrappers::MPI::Vector &) {
        return result.negative_curvature ? SolverControl::failure :
                                           SolverControl::success;
      });
      bool converged = true;
      try
        {
          solver.solve(matrix, solution, rhs, amg);
        }
      catch (const SolverControl::NoConvergence &)
        {
          // Every rank sees the same global norms: every rank gets here.
          converged = false;
        }
      result.iterations += control.last_step();
      result.relative_residual = control.last_value();
      return converged;
    }

    Result
    LinearSystem::solve(const Vector<double> &prescribed) const
    {
      Assert(amg != nullptr,
             ExcMessage("LinearSystem::build_preconditioner() first."));
      const Scene    &scene = layout->scene;
      const MPI_Comm  comm  = layout->communicator;
      const IndexSet &owned = layout->locally_owned_dofs;

      // -K_fj u_j on the free rows, from each cell's stiffness and the
      // planning's join values (the constraints' inhomogeneities).
      AffineConstraints<double> joins(layout->locally_relevant_dofs);
      for (const auto dof : layout->locally_relevant_dofs)
        if (join_rows.is_constrained(dof))
          {
            joins.add_line(dof);
            joins.set_inhomogeneity(dof, prescribed[layout->serial_dof(dof)]);
          }
      joins.close();
      TrilinosWrappers::MPI::Vector        rhs(owned, comm);
      const auto                           A = tangents(scene);
      FullMatrix<double>                   cell_matrix(12, 12);
      Vector<double>                       cell_rhs(12);
      std::vector<types::global_dof_index> dofs(12);
      for (const auto &cell : layout->dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            bool touches_join = false;
            for (const unsigned int v : cell->vertex_indices())
              touches_join |=
                joins.is_constrained(cell->vertex_dof_index(v, 0));
            if (!touches_join)
              continue;
            cell_stiffness(*layout, A, cell, cell_matrix, dofs);
            joins.distribute_local_to_global(cell_rhs, dofs, rhs, cell_matrix);
          }
      // The nodal body force (gravity) on the free DoFs, as the rank
      // decided it.
      if (scene.has_body_force())
        for (const auto dof : owned)
          if (!joins.is_constrained(dof))
            rhs[dof] += layout->body_force()[dof];
      rhs.compress(VectorOperation::add);

      // The relative tolerance means what it means in the serial model,
      // whose right-hand side holds |K_jj| u_j on the join rows as well
      // (ConstrainedSystem::right_hand_side), where this one holds 0.
      double join_norm = 0.;
      for (const auto dof : owned)
        if (joins.is_constrained(dof))
          join_norm += Utilities::fixed_power<2>(
            join_diagonal[owned.index_within_set(dof)] *
            prescribed[layout->serial_dof(dof)]);
      const double serial_rhs_norm =
        std::sqrt(Utilities::fixed_power<2>(rhs.l2_norm()) +
                  Utilities::MPI::sum(join_norm, comm));

      Result                        result;
      TrilinosWrappers::MPI::Vector solution(owned, comm);
      LinearSolver::Result          cg_result;
      result.converged              = cg(stiffness->matrix(),
                            *amg,
                            rhs,
                            solution,
                            parameters.relative_tolerance * serial_rhs_norm,
                            parameters.max_iterations,
                            cg_result);
      result.iterations             = cg_result.iterations;
      const bool negative_curvature = cg_result.negative_curvature;
      TrilinosWrappers::MPI::Vector residual(owned, comm);
      stiffness->matrix().vmult(residual, solution);
      residual -= rhs;
      result.relative_residual =
        serial_rhs_norm > 0. ? residual.l2_norm() / serial_rhs_norm : 0.;
      if (!result.converged)
        {
          std::ostringstream m;
          m << "Linear elasticity on " << Utilities::MPI::n_mpi_processes(comm)
            << " ranks: CG did not converge in " << result.iterations
            << " iterations (relative residual " << result.relative_residual
            << ")"
            << (negative_curvature ?
                  ": it found negative curvature, the stiffness is not "
                  "positive definite." :
                  ".");
          throw Error(m.str());
        }
      joins.distribute(solution);
      result.displacement = layout->gather(solution);
      return result;
    }

    Result
    solve_linear(const DistributedLayout        &layout,
                 const Vector<double>           &prescribed,
                 const LinearSolver::Parameters &parameters)
    {
      LinearSystem system;
      system.assemble(layout, parameters);
      system.build_preconditioner();
      return system.solve(prescribed);
    }
  } // namespace DistributedElasticity
} // namespace softface

// The Newton tangent and forces of a nonlinear FEM model on several MPI ranks
// (issue 20): cells added on their rank, the tangent a Trilinos matrix, the
// join DoFs eliminated in place and CG with ML. See fe/distributed_tangent.h.

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/trilinos_index_access.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <softface/fe/distributed_elasticity.h>
#include <softface/fe/distributed_tangent.h>

#include <Epetra_CrsMatrix.h>

#include <algorithm>
#include <cmath>

namespace softface
{
  DistributedTangent::DistributedTangent(
    const DistributedLayout        &layout,
    const LinearSolver::Parameters &parameters)
      : layout(layout)
      , parameters(parameters)
  {
    const MPI_Comm comm = layout.communicator;
    // Every coupling of the layout, join DoFs included: the right-hand side
    // needs the join columns before they are eliminated.
    TrilinosWrappers::SparsityPattern sparsity(layout.locally_owned_dofs,
                                               layout.locally_owned_dofs,
                                               layout.locally_relevant_dofs,
                                               comm);
    DoFTools::make_sparsity_pattern(layout.dof_handler,
                                    sparsity,
                                    AffineConstraints<double>(),
                                    /*keep_constrained_dofs=*/true,
                                    Utilities::MPI::this_mpi_process(comm));
    sparsity.compress();
    tangent.reinit(sparsity);
    forces.reinit(layout.locally_owned_dofs, comm);
    // Zeroing compresses the matrix, which settles its storage (deal.II
    // optimises it then): the positions set_cells() finds stay valid.
    tangent = 0.;

    // Which rows and columns are join DoFs, found once (the elimination
    // runs at every Newton iteration).
    const auto &matrix = tangent.trilinos_matrix();
    row_serial_dof.resize(matrix.NumMyRows());
    row_is_join.resize(matrix.NumMyRows());
    diagonal_column.resize(matrix.NumMyRows());
    for (int r = 0; r < matrix.NumMyRows(); ++r)
      {
        const auto dof    = TrilinosWrappers::global_row_index(matrix, r);
        row_serial_dof[r] = layout.serial_dof(dof);
        row_is_join[r]    = layout.is_join_dof(dof);
        diagonal_column[r] =
          matrix.LCID(static_cast<TrilinosWrappers::types::int_type>(dof));
      }
    // Every column of an owned row is a locally relevant DoF (a cell at an
    // owned vertex is an owned or a ghost cell).
    column_is_join.resize(matrix.NumMyCols());
    for (int c = 0; c < matrix.NumMyCols(); ++c)
      column_is_join[c] =
        layout.is_join_dof(TrilinosWrappers::global_column_index(matrix, c));
  }

  void
  DistributedTangent::set_cells(
    const std::vector<std::array<types::global_dof_index, 12>> &cell_dofs)
  {
    const auto &matrix = tangent.trilinos_matrix();
    // A row's place among this rank's rows is its place in the forces too.
    AssertThrow(matrix.RowMap().SameAs(forces.trilinos_vector().Map()),
                ExcInternalError());
    cell_row.assign(12 * cell_dofs.size(), -1);
    cell_entry.assign(144 * cell_dofs.size(), -1);
    for (unsigned int c = 0; c < cell_dofs.size(); ++c)
      for (unsigned int r = 0; r < 12; ++r)
        {
          const int local_row = matrix.LRID(
            static_cast<TrilinosWrappers::types::int_type>(cell_dofs[c][r]));
          if (local_row < 0)
            continue;
          cell_row[12 * c + r] = local_row;
          int     n_entries;
          double *values;
          int    *columns;
          const_cast<Epetra_CrsMatrix &>(matrix).ExtractMyRowView(local_row,
                                                                  n_entries,
                                                                  values,
                                                                  columns);
          for (unsigned int q = 0; q < 12; ++q)
            {
              const int column =
                matrix.LCID(static_cast<TrilinosWrappers::types::int_type>(
                  cell_dofs[c][q]));
              const int *found =
                std::find(columns, columns + n_entries, column);
              AssertThrow(column >= 0 && found != columns + n_entries,
                          ExcInternalError());
              cell_entry[144 * c + 12 * r + q] = found - columns;
            }
        }
  }

  void
  DistributedTangent::begin_assembly(const bool with_tangent_in)
  {
    with_tangent = with_tangent_in;
    forces       = 0.;
    if (!with_tangent)
      return;
    tangent = 0.;
    // Where each row's values are now (looked up again after every
    // compression, which may move them).
    auto &matrix = const_cast<Epetra_CrsMatrix &>(tangent.trilinos_matrix());
    row_values.resize(matrix.NumMyRows());
    for (int local_row = 0; local_row < matrix.NumMyRows(); ++local_row)
      {
        int  n_entries;
        int *columns;
        matrix.ExtractMyRowView(local_row,
                                n_entries,
                                row_values[local_row],
                                columns);
      }
  }

  void
  DistributedTangent::add_cell(const unsigned int            cell,
                               const Elasticity::P1Response &response)
  {
    double *owned_forces = forces.trilinos_vector()[0];
    for (unsigned int r = 0; r < 12; ++r)
      {
        const int local_row = cell_row[12 * cell + r];
        if (local_row < 0)
          continue;
        owned_forces[local_row] += response.force[r / 3][r % 3];
        if (!with_tangent)
          continue;
        double    *values = row_values[local_row];
        const int *entry  = &cell_entry[144 * cell + 12 * r];
        for (unsigned int b = 0; b < 4; ++b)
          for (unsigned int j = 0; j < 3; ++j)
            values[*entry++] += response.tangent[r / 3][b][r % 3][j];
      }
  }

  void
  DistributedTangent::end_assembly(Vector<double> &serial_forces)
  {
    serial_forces = layout.gather(forces);
  }

  void
  DistributedTangent::right_hand_side_and_eliminate(
    const Vector<double> &join_increment,
    const Vector<double> &residual,
    Vector<double>       &rhs)
  {
    const MPI_Comm                comm  = layout.communicator;
    const IndexSet               &owned = layout.locally_owned_dofs;
    TrilinosWrappers::MPI::Vector d(owned, comm), Kd(owned, comm),
      rhs_owned(owned, comm);
    // By this rank's rows (the vectors' and the matrix's local order).
    double *const d_local   = d.trilinos_vector()[0];
    double *const Kd_local  = Kd.trilinos_vector()[0];
    double *const rhs_local = rhs_owned.trilinos_vector()[0];
    const int     n_rows    = row_serial_dof.size();
    for (int r = 0; r < n_rows; ++r)
      if (row_is_join[r])
        d_local[r] = join_increment[row_serial_dof[r]];
    tangent.vmult(Kd, d);

    // The elimination in place, row by row of this rank's rows, as
    // ConstrainedSystem::eliminate_join_dofs() does on the serial matrix;
    // the join rows' right-hand side scaled by their diagonal before.
    auto &matrix = const_cast<Epetra_CrsMatrix &>(tangent.trilinos_matrix());
    for (int r = 0; r < n_rows; ++r)
      {
        int     n_entries;
        double *values;
        int    *columns;
        matrix.ExtractMyRowView(r, n_entries, values, columns);
        if (!row_is_join[r])
          {
            rhs_local[r] = -(Kd_local[r] + residual[row_serial_dof[r]]);
            for (int k = 0; k < n_entries; ++k)
              if (column_is_join[columns[k]])
                values[k] = 0.;
            continue;
          }
        for (int k = 0; k < n_entries; ++k)
          if (columns[k] == diagonal_column[r])
            {
              values[k]    = values[k] != 0. ? std::abs(values[k]) : 1.;
              rhs_local[r] = values[k] * d_local[r];
            }
          else
            values[k] = 0.;
      }
    rhs = layout.gather(rhs_owned);
  }

  void
  DistributedTangent::build_amg()
  {
    // On a copy, as the serial LinearSolver: ML's finest level refers to
    // its matrix, and the tangent is overwritten by every assembly (its
    // smoother then met a matrix other than the one its Chebyshev bounds
    // were estimated for, and CG found negative curvature).
    amg_matrix.copy_from(tangent);
    amg = std::make_unique<TrilinosWrappers::PreconditionAMG>();
    DistributedElasticity::build_amg(layout, parameters, amg_matrix, *amg);
    ++amg_builds;
  }

  LinearSolver::Result
  DistributedTangent::solve(const Vector<double> &rhs, Vector<double> &du)
  {
    Assert(amg != nullptr,
           ExcMessage("DistributedTangent::build_amg() first."));
    const MPI_Comm                comm = layout.communicator;
    TrilinosWrappers::MPI::Vector b(layout.locally_owned_dofs, comm),
      x(layout.locally_owned_dofs, comm);
    layout.scatter(rhs, b);
    // The serial solver's tolerance: relative to the whole right-hand side
    // (every rank holds it).
    const double tolerance = parameters.relative_tolerance * rhs.l2_norm();
    LinearSolver::Result result;
    if (parameters.amg_rebuild_iterations == 0)
      result.converged = DistributedElasticity::cg(
        tangent, *amg, b, x, tolerance, parameters.max_iterations, result);
    else
      {
        // As LinearSolver::solve(): a slow solve continues with ML rebuilt
        // on this tangent; one over the limit rebuilds it for the next.
        const unsigned int first_attempt =
          std::min(parameters.max_iterations,
                   2 * parameters.amg_rebuild_iterations);
        result.converged = DistributedElasticity::cg(
          tangent, *amg, b, x, tolerance, first_attempt, result);
        if (!result.converged && !result.negative_curvature &&
            first_attempt < parameters.max_iterations)
          {
            build_amg();
            result.converged =
              DistributedElasticity::cg(tangent,
                                        *amg,
                                        b,
                                        x,
                                        tolerance,
                                        parameters.max_iterations -
                                          first_attempt,
                                        result);
          }
        else if (result.iterations > parameters.amg_rebuild_iterations)
          build_amg();
      }
    TrilinosWrappers::MPI::Vector r(layout.locally_owned_dofs, comm);
    tangent.vmult(r, x);
    r -= b;
    result.relative_residual = r.l2_norm() / std::max(rhs.l2_norm(), 1e-300);
    du                       = layout.gather(x);
    return result;
  }

  unsigned int
  DistributedTangent::n_amg_builds() const
  {
    return amg_builds;
  }
} // namespace softface

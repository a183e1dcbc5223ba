// The Newton tangent and forces of a nonlinear FEM model on several MPI
// ranks: cells added on the ranks that own their rows, the tangent a
// Trilinos matrix, the join DoFs eliminated in place and CG with ML. See
// fe/distributed_tangent.h.

#include <deal.II/dofs/dof_tools.h>

#include <softface/fe/distributed_elasticity.h>
#include <softface/fe/distributed_tangent.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <algorithm>

namespace softface
{
  DistributedTangent::DistributedTangent(
    const DoFHandler<3>                        &dof_handler,
    const std::vector<types::global_dof_index> &serial_dof_of_relevant,
    const std::vector<bool>                    &serial_is_join,
    const std::vector<Point<3>>                &serial_points,
    const std::vector<unsigned int>            &serial_component,
    const LinearSolver::Parameters             &parameters,
    const Point<3>                             *points_centroid)
      : communicator(dof_handler.get_communicator())
      , locally_owned_dofs(dof_handler.locally_owned_dofs())
      , n_serial_dofs(serial_is_join.size())
      , parameters(parameters)
  {
    IndexSet relevant_dofs;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_dofs);
    AssertThrow(relevant_dofs.n_elements() == serial_dof_of_relevant.size(),
                ExcInternalError());
    std::vector<char> relevant_is_join(relevant_dofs.n_elements());
    for (unsigned int k = 0; k < relevant_is_join.size(); ++k)
      relevant_is_join[k] = serial_is_join[serial_dof_of_relevant[k]];
    tangent =
      std::make_unique<OwnedRowsMatrix>(locally_owned_dofs,
                                        relevant_dofs,
                                        relevant_is_join,
                                        OwnedRowsMatrix::JoinCouplings::kept,
                                        communicator);

    // This rank's rows, in the order of its owned DoFs (the matrix's and the
    // vectors' local order): their serial DoFs, join flags and ML's null
    // space (rotations about the centroid of all the model's DoF points, as
    // the serial LinearSolver takes them: from every rank's whole points, or
    // given by the model where a rank holds its own only).
    const unsigned int n_rows = locally_owned_dofs.n_elements();
    row_serial_dof.resize(n_rows);
    row_is_join.resize(n_rows);
    owned_points.resize(n_rows);
    owned_component.resize(n_rows);
    for (unsigned int r = 0; r < n_rows; ++r)
      {
        const auto serial =
          serial_dof_of_relevant[relevant_dofs.index_within_set(
            locally_owned_dofs.nth_index_in_set(r))];
        row_serial_dof[r]  = serial;
        row_is_join[r]     = serial_is_join[serial];
        owned_points[r]    = serial_points[serial];
        owned_component[r] = serial_component[serial];
      }
    if (points_centroid != nullptr)
      centroid = *points_centroid;
    else
      {
        for (const auto &p : serial_points)
          centroid += p;
        centroid /= std::max<std::size_t>(serial_points.size(), 1);
      }
    forces.reinit(locally_owned_dofs, communicator);
  }

  void
  DistributedTangent::set_cells(
    const std::vector<types::global_dof_index> &cell_dofs,
    const unsigned int                          n)
  {
    tangent->set_cells(cell_dofs, n);
    dofs_per_cell = n;
    // A row's place among this rank's rows is its place in the forces too.
    AssertThrow(tangent->matrix().trilinos_matrix().RowMap().SameAs(
                  forces.trilinos_vector().Map()),
                ExcInternalError());
  }

  void
  DistributedTangent::begin_assembly(const bool with_tangent_in)
  {
    with_tangent = with_tangent_in;
    forces       = 0.;
    if (with_tangent)
      tangent->zero();
  }

  void
  DistributedTangent::add_cell(const unsigned int        cell,
                               const Vector<double>     &cell_forces,
                               const FullMatrix<double> &cell_tangent)
  {
    double *owned_forces = forces.trilinos_vector()[0];
    for (unsigned int i = 0; i < dofs_per_cell; ++i)
      {
        const int r = tangent->row(cell, i);
        if (r < 0)
          continue;
        owned_forces[r] += cell_forces[i];
        if (with_tangent)
          tangent->add_row(cell, i, [&](const unsigned int q) {
            return cell_tangent(i, q);
          });
      }
  }

  void
  DistributedTangent::add_cell(const unsigned int            cell,
                               const Elasticity::P1Response &response)
  {
    Assert(dofs_per_cell == 12, ExcInternalError());
    double *owned_forces = forces.trilinos_vector()[0];
    for (unsigned int i = 0; i < 12; ++i)
      {
        const int r = tangent->row(cell, i);
        if (r < 0)
          continue;
        owned_forces[r] += response.force[i / 3][i % 3];
        if (with_tangent)
          tangent->add_row(cell, i, [&](const unsigned int q) {
            return response.tangent[i / 3][q / 3][i % 3][q % 3];
          });
      }
  }

  Vector<double>
  DistributedTangent::gather(
    const TrilinosWrappers::MPI::Vector &owned_values) const
  {
    // Each rank writes its entries into a zero serial vector; the sum over
    // the ranks is the whole vector, since every DoF has one owner.
    Vector<double> serial(n_serial_dofs);
    const double  *local = owned_values.trilinos_vector()[0];
    for (unsigned int r = 0; r < row_serial_dof.size(); ++r)
      serial[row_serial_dof[r]] = local[r];
    Utilities::MPI::sum(serial, communicator, serial);
    return serial;
  }

  void
  DistributedTangent::end_assembly(Vector<double> &serial_forces)
  {
    serial_forces = gather(forces);
  }

  void
  DistributedTangent::right_hand_side_and_eliminate(
    const Vector<double> &join_increment,
    const Vector<double> &residual,
    Vector<double>       &rhs)
  {
    TrilinosWrappers::MPI::Vector d(locally_owned_dofs, communicator),
      Kd(locally_owned_dofs, communicator),
      rhs_owned(locally_owned_dofs, communicator);
    // By this rank's rows (the vectors' and the matrix's local order).
    double *const d_local   = d.trilinos_vector()[0];
    double *const Kd_local  = Kd.trilinos_vector()[0];
    double *const rhs_local = rhs_owned.trilinos_vector()[0];
    const int     n_rows    = row_serial_dof.size();
    for (int r = 0; r < n_rows; ++r)
      if (row_is_join[r])
        d_local[r] = join_increment[row_serial_dof[r]];
    tangent->matrix().vmult(Kd, d);
    // The join rows' right-hand side scaled by their diagonal as the
    // elimination leaves it (ConstrainedSystem on one rank).
    const std::vector<double> diagonal = tangent->eliminate_join_dofs();
    for (int r = 0; r < n_rows; ++r)
      rhs_local[r] = row_is_join[r] ?
                       diagonal[r] * d_local[r] :
                       -(Kd_local[r] + residual[row_serial_dof[r]]);
    rhs = gather(rhs_owned);
  }

  void
  DistributedTangent::build_amg()
  {
    // On a copy, as the serial LinearSolver: ML's finest level refers to
    // its matrix, and the tangent is overwritten by every assembly (its
    // smoother then met a matrix other than the one its Chebyshev bounds
    // were estimated for, and CG found negative curvature).
    amg_matrix.copy_from(tangent->matrix());
    amg = std::make_unique<TrilinosWrappers::PreconditionAMG>();
    Teuchos::ParameterList list;
    const auto             null_space = LinearSolver::amg_parameters(
      parameters, amg_matrix, owned_points, owned_component, centroid, list);
    amg->initialize(amg_matrix, list);
    ++amg_builds;
  }

  LinearSolver::Result
  DistributedTangent::solve(const Vector<double> &rhs, Vector<double> &du)
  {
    Assert(amg != nullptr,
           ExcMessage("DistributedTangent::build_amg() first."));
    TrilinosWrappers::MPI::Vector b(locally_owned_dofs, communicator),
      x(locally_owned_dofs, communicator);
    double *const b_local = b.trilinos_vector()[0];
    for (unsigned int r = 0; r < row_serial_dof.size(); ++r)
      b_local[r] = rhs[row_serial_dof[r]];
    // The serial solver's tolerance: relative to the whole right-hand side
    // (every rank holds it).
    const double tolerance = parameters.relative_tolerance * rhs.l2_norm();
    LinearSolver::Result result;
    if (parameters.amg_rebuild_iterations == 0)
      result.converged = DistributedElasticity::cg(tangent->matrix(),
                                                   *amg,
                                                   b,
                                                   x,
                                                   tolerance,
                                                   parameters.max_iterations,
                                                   result);
    else
      {
        // As LinearSolver::solve(): a slow solve continues with ML rebuilt
        // on this tangent; one over the limit rebuilds it for the next.
        const unsigned int first_attempt =
          std::min(parameters.max_iterations,
                   2 * parameters.amg_rebuild_iterations);
        result.converged = DistributedElasticity::cg(
          tangent->matrix(), *amg, b, x, tolerance, first_attempt, result);
        if (!result.converged && !result.negative_curvature &&
            first_attempt < parameters.max_iterations)
          {
            build_amg();
            result.converged =
              DistributedElasticity::cg(tangent->matrix(),
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
    // cg() leaves CG's last residual norm there.
    result.relative_residual /= std::max(rhs.l2_norm(), 1e-300);
    du = gather(x);
    return result;
  }

  unsigned int
  DistributedTangent::n_amg_builds() const
  {
    return amg_builds;
  }
} // namespace softface

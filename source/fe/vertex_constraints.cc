// Constraints on free vertices for the FEM models (fe): sliding contact and
// the lips' contact as AffineConstraints lines, the constrained solve and
// the active-set update of unilateral constraints.

#include <softface/core/error.h>
#include <softface/fe/vertex_constraints.h>

#include <cmath>
#include <sstream>

namespace softface
{
  VertexConstraintSet::VertexConstraintSet(const Scene &scene)
      : n_dofs(scene.dof_handler.n_dofs())
  {
    const auto &dofs = scene.vertex_dofs();
    for (const VertexConstraint &c : scene.effects.vertex_constraints)
      {
        Line line;
        line.a          = dofs[c.vertex];
        line.partnered  = c.partner != numbers::invalid_unsigned_int;
        line.b          = line.partnered ? dofs[c.partner] : line.a;
        line.n          = c.normal / c.normal.norm();
        line.unilateral = c.unilateral;
        line.slave      = 0;
        for (unsigned int i = 1; i < 3; ++i)
          if (std::abs(line.n[i]) > std::abs(line.n[line.slave]))
            line.slave = i;
        constraint_lines.push_back(line);
      }
    is_holding.assign(constraint_lines.size(), true);
    build_lines();
  }

  unsigned int
  VertexConstraintSet::size() const
  {
    return constraint_lines.size();
  }

  const std::vector<bool> &
  VertexConstraintSet::holding() const
  {
    return is_holding;
  }

  unsigned int
  VertexConstraintSet::n_holding() const
  {
    return std::count(is_holding.begin(), is_holding.end(), true);
  }

  bool
  VertexConstraintSet::has_unilateral() const
  {
    for (const Line &line : constraint_lines)
      if (line.unilateral)
        return true;
    return false;
  }

  void
  VertexConstraintSet::build_lines()
  {
    make_lines(is_holding, homogeneous);
  }

  void
  VertexConstraintSet::make_lines(const std::vector<bool>   &holding,
                                  AffineConstraints<double> &lines) const
  {
    lines.clear();
    for (unsigned int c = 0; c < constraint_lines.size(); ++c)
      {
        if (!holding[c])
          continue;
        // n . u_a - n . u_b = g, solved for a's component 'slave'.
        const Line  &line = constraint_lines[c];
        const double ns   = line.n[line.slave];
        lines.add_line(line.a[line.slave]);
        for (unsigned int i = 0; i < 3; ++i)
          {
            if (i != line.slave && line.n[i] != 0.)
              lines.add_entry(line.a[line.slave], line.a[i], -line.n[i] / ns);
            if (line.partnered && line.n[i] != 0.)
              lines.add_entry(line.a[line.slave], line.b[i], line.n[i] / ns);
          }
      }
    lines.close();
  }

  void
  VertexConstraintSet::add_fill(DynamicSparsityPattern &dsp) const
  {
    // A released constraint's slave is an ordinary DoF: the others' masters
    // couple to it too (condensing with every line would not add that).
    AffineConstraints<double> all;
    for (const Line &line : constraint_lines)
      {
        const auto                           slave = line.a[line.slave];
        std::vector<types::global_dof_index> masters;
        for (unsigned int i = 0; i < 3; ++i)
          {
            if (i != line.slave)
              masters.push_back(line.a[i]);
            if (line.partnered)
              masters.push_back(line.b[i]);
          }
        std::vector<types::global_dof_index> columns;
        for (auto entry = dsp.begin(slave); entry != dsp.end(slave); ++entry)
          columns.push_back(entry->column());
        for (const auto m : masters)
          for (const auto c : columns)
            {
              dsp.add(m, c);
              dsp.add(c, m);
            }
      }
    // And the masters of coupled slaves to each other.
    make_lines(std::vector<bool>(constraint_lines.size(), true), all);
    all.condense(dsp);
  }

  double
  VertexConstraintSet::gap(const unsigned int    c,
                           const Vector<double> &u,
                           const Vector<double> &prescribed,
                           const double          load) const
  {
    const Line &line = constraint_lines[c];
    double      g    = 0.;
    for (unsigned int i = 0; i < 3; ++i)
      {
        g += line.n[i] * u[line.a[i]];
        if (line.partnered)
          g -= line.n[i] * u[line.b[i]];
        else
          g -= load * line.n[i] * prescribed[line.a[i]];
      }
    return g;
  }

  const AffineConstraints<double> &
  VertexConstraintSet::lines() const
  {
    return homogeneous;
  }

  void
  VertexConstraintSet::closing_increment(const Vector<double> &u,
                                         const Vector<double> &prescribed,
                                         const double          load,
                                         Vector<double>       &increment) const
  {
    increment.reinit(n_dofs);
    for (unsigned int c = 0; c < constraint_lines.size(); ++c)
      if (is_holding[c])
        {
          const Line &line = constraint_lines[c];
          increment[line.a[line.slave]] =
            -gap(c, u, prescribed, load) / line.n[line.slave];
        }
  }

  void
  VertexConstraintSet::condense(SparseMatrix<double> &matrix) const
  {
    std::vector<std::pair<types::global_dof_index, double>> diagonal;
    for (unsigned int c = 0; c < constraint_lines.size(); ++c)
      if (is_holding[c])
        {
          const auto slave = constraint_lines[c].a[constraint_lines[c].slave];
          diagonal.emplace_back(slave, matrix.diag_element(slave));
        }
    homogeneous.condense(matrix);
    for (const auto &[slave, value] : diagonal)
      matrix.diag_element(slave) = value;
  }

  void
  VertexConstraintSet::condense(Vector<double> &v) const
  {
    homogeneous.condense(v);
  }

  LinearSolver::Result
  VertexConstraintSet::solve(const SparseMatrix<double> &eliminated,
                             LinearSolver               &solver,
                             const Vector<double>       &closing,
                             const Vector<double>       &rhs,
                             Vector<double>             &du) const
  {
    // du = closing + C x:  C^T K C x = C^T (rhs - K closing).
    Vector<double> r(rhs.size());
    eliminated.vmult(r, closing);
    r.sadd(-1., 1., rhs);
    homogeneous.condense(r);
    du.reinit(rhs.size());
    const LinearSolver::Result result = solver.solve(r, du);
    homogeneous.distribute(du);
    du += closing;
    return result;
  }

  void
  VertexConstraintSet::condense_for_holding(
    const SparseMatrix<double> &eliminated,
    SparseMatrix<double>       &condensed,
    std::vector<bool>          &condensed_for,
    LinearSolver               &solver,
    const std::string          &model) const
  {
    if (condensed_for == is_holding)
      return;
    condensed.reinit(eliminated.get_sparsity_pattern());
    condensed.copy_from(eliminated);
    condense(condensed);
    condensed_for = is_holding;
    if (!solver.set_matrix(condensed))
      throw Error(model + " (direct): the Cholesky factorisation failed; the "
                          "constrained stiffness is not positive definite.");
  }

  VertexConstraintSet::ActiveSetReport
  VertexConstraintSet::solve_with_active_set(
    const SparseMatrix<double> &unconstrained,
    const SparseMatrix<double> &eliminated,
    SparseMatrix<double>       &condensed,
    std::vector<bool>          &condensed_for,
    LinearSolver               &solver,
    const Vector<double>       &rhs,
    const Vector<double>       &prescribed,
    const Vector<double>       *minus_forces,
    const unsigned int          max_rounds,
    const std::string          &model,
    Vector<double>             &u)
  {
    // Solve with the constraints that hold; a unilateral one that pulls is
    // released, one passed through made to hold, until none changes.
    ActiveSetReport    report;
    unsigned int       changes = 0;
    const unsigned int n       = rhs.size();
    do
      {
        if (report.rounds == max_rounds)
          throw Error(model + ": the contact's active set still changed (" +
                      std::to_string(changes) + " constraints) after " +
                      std::to_string(report.rounds) +
                      " solves; raise 'Maximum active-set iterations'.");
        ++report.rounds;
        condense_for_holding(
          eliminated, condensed, condensed_for, solver, model);
        Vector<double> zero(n), closing;
        closing_increment(zero, prescribed, 1., closing);
        const LinearSolver::Result one =
          solve(eliminated, solver, closing, rhs, u);
        report.result.converged = one.converged;
        report.result.iterations += one.iterations;
        report.result.relative_residual = one.relative_residual;
        if (!one.converged || !has_unilateral())
          break;
        // K u - f: the constraint forces at the constrained vertices.
        Vector<double> unbalanced(n);
        unconstrained.vmult(unbalanced, u);
        if (minus_forces != nullptr)
          unbalanced += *minus_forces;
        changes = update_active_set(u, prescribed, unbalanced);
    } while (changes > 0);
    return report;
  }

  unsigned int
  VertexConstraintSet::update_active_set(const Vector<double> &u,
                                         const Vector<double> &prescribed,
                                         const Vector<double> &unbalanced,
                                         const double          load)
  {
    // Scales for "numerically zero": the largest contact pressure and the
    // largest displacement.
    double pressure_scale = 0.;
    for (unsigned int c = 0; c < constraint_lines.size(); ++c)
      {
        const Line &line = constraint_lines[c];
        double      p    = 0.;
        for (unsigned int i = 0; i < 3; ++i)
          p += line.n[i] * unbalanced[line.a[i]];
        pressure_scale = std::max(pressure_scale, std::abs(p));
      }
    const double length_scale = std::max(u.linfty_norm(), 1e-300);

    unsigned int changes = 0;
    for (unsigned int c = 0; c < constraint_lines.size(); ++c)
      {
        const Line &line = constraint_lines[c];
        if (!line.unilateral)
          continue;
        if (is_holding[c])
          {
            // K u - f at a is the force the constraint exerts on the
            // tissue: along +n it presses, along -n it would pull.
            double p = 0.;
            for (unsigned int i = 0; i < 3; ++i)
              p += line.n[i] * unbalanced[line.a[i]];
            if (p < -1e-8 * pressure_scale)
              {
                is_holding[c] = false;
                ++changes;
              }
          }
        else if (gap(c, u, prescribed, load) < -1e-10 * length_scale)
          {
            is_holding[c] = true;
            ++changes;
          }
      }
    if (changes > 0)
      build_lines();
    return changes;
  }

  std::string
  VertexConstraintSet::describe() const
  {
    std::ostringstream s;
    s << "holding " << n_holding() << " of " << size();
    return s.str();
  }
} // namespace softface

#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <softface/core/error.h>
#include <softface/fe/hyperelasticity.h>

#include <algorithm>
#include <numeric>

#include <cmath>

namespace softface
{
  namespace Hyperelasticity
  {
    Law
    law_from_name(const std::string &name)
    {
      if (name == "st venant-kirchhoff")
        return Law::st_venant_kirchhoff;
      if (name == "neo-hooke")
        return Law::neo_hooke;
      if (name == "linear")
        return Law::linear;
      throw Error("Unknown material law '" + name + "'.");
    }

    std::string
    law_name(const Law law)
    {
      switch (law)
        {
          case Law::st_venant_kirchhoff:
            return "st venant-kirchhoff";
          case Law::neo_hooke:
            return "neo-hooke";
          case Law::linear:
            return "linear";
        }
      return "";
    }

    bool
    cell_response(const Law                          law,
                  const double                       lambda,
                  const double                       mu,
                  const std::array<Tensor<1, 3>, 4> &grad,
                  const double                       volume,
                  const std::array<Tensor<1, 3>, 4> &u,
                  const bool                         with_tangent,
                  CellResponse                      &response)
    {
      Tensor<2, 3> F = unit_symmetric_tensor<3>();
      for (unsigned int a = 0; a < 4; ++a)
        F += outer_product(u[a], grad[a]);
      const double J = determinant(F);
      if (!(J > 0.) && law != Law::linear)
        return false;

      // First Piola-Kirchhoff stress P and, for the tangent, the pieces of
      // dP/dF contracted with the shape gradients (derived in the comments).
      Tensor<2, 3> P;
      Tensor<2, 3> S, b, F_inverse_transpose;
      double       log_J = 0.;
      if (law == Law::st_venant_kirchhoff)
        {
          const Tensor<2, 3> E =
            0.5 * (transpose(F) * F - Tensor<2, 3>(unit_symmetric_tensor<3>()));
          const double trace_E = trace(E);
          S = lambda * trace_E * Tensor<2, 3>(unit_symmetric_tensor<3>()) +
              2. * mu * E;
          P               = F * S;
          b               = F * transpose(F);
          response.energy = volume * (0.5 * lambda * trace_E * trace_E +
                                      mu * scalar_product(E, E));
        }
      else if (law == Law::linear)
        {
          const Tensor<2, 3> I      = unit_symmetric_tensor<3>();
          const Tensor<2, 3> strain = 0.5 * (F + transpose(F)) - I;
          P = lambda * trace(strain) * I + 2. * mu * strain;
          response.energy =
            volume * (0.5 * lambda * trace(strain) * trace(strain) +
                      mu * scalar_product(strain, strain));
        }
      else
        {
          F_inverse_transpose = transpose(invert(F));
          log_J               = std::log(J);
          P = mu * F + (lambda * log_J - mu) * F_inverse_transpose;
          response.energy =
            volume * (0.5 * mu * (scalar_product(F, F) - 3.) - mu * log_J +
                      0.5 * lambda * log_J * log_J);
        }
      for (unsigned int a = 0; a < 4; ++a)
        response.force[a] = volume * (P * grad[a]);

      if (!with_tangent)
        return true;
      if (law == Law::st_venant_kirchhoff)
        {
          // dP_iJ/dF_kL = delta_ik S_JL + lambda F_iJ F_kL + mu F_iL F_kJ
          //               + mu (F F^T)_ik delta_JL
          std::array<Tensor<1, 3>, 4> Fg, Sg;
          for (unsigned int a = 0; a < 4; ++a)
            Fg[a] = F * grad[a], Sg[a] = S * grad[a];
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int c = 0; c < 4; ++c)
              {
                const double  geometric = grad[a] * Sg[c];
                const double  gg        = grad[a] * grad[c];
                Tensor<2, 3> &K         = response.tangent[a][c];
                for (unsigned int i = 0; i < 3; ++i)
                  for (unsigned int k = 0; k < 3; ++k)
                    K[i][k] =
                      volume * ((i == k ? geometric : 0.) +
                                lambda * Fg[a][i] * Fg[c][k] +
                                mu * Fg[c][i] * Fg[a][k] + mu * b[i][k] * gg);
              }
        }
      else
        {
          // dP_iJ/dF_kL = mu delta_ik delta_JL + lambda F^-T_iJ F^-T_kL
          //               - (lambda ln J - mu) F^-1_Jk F^-1_Li
          // At F = I this is the linear law's (constant) derivative
          //   lambda delta_iJ delta_kL + mu (delta_ik delta_JL + delta_iL
          //   delta_kJ).
          const bool                  linear = (law == Law::linear);
          std::array<Tensor<1, 3>, 4> Hg;
          for (unsigned int a = 0; a < 4; ++a)
            Hg[a] = linear ? grad[a] : F_inverse_transpose * grad[a];
          const double c2 = linear ? -mu : lambda * log_J - mu;
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int c = 0; c < 4; ++c)
              {
                const double  gg = grad[a] * grad[c];
                Tensor<2, 3> &K  = response.tangent[a][c];
                for (unsigned int i = 0; i < 3; ++i)
                  for (unsigned int k = 0; k < 3; ++k)
                    K[i][k] = volume * ((i == k ? mu * gg : 0.) +
                                        lambda * Hg[a][i] * Hg[c][k] -
                                        c2 * Hg[c][i] * Hg[a][k]);
              }
        }
      return true;
    }

    bool
    material_response(const Law           law,
                      const double        lambda,
                      const double        mu,
                      const Tensor<2, 3> &F,
                      Tensor<2, 3>       &P,
                      Tensor<4, 3>       *A)
    {
      const double J = determinant(F);
      if (!(J > 0.) && law != Law::linear)
        return false;
      const Tensor<2, 3> I = unit_symmetric_tensor<3>();
      if (law == Law::linear)
        {
          const Tensor<2, 3> strain = 0.5 * (F + transpose(F)) - I;
          P = lambda * trace(strain) * I + 2. * mu * strain;
          if (A != nullptr)
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int J_ = 0; J_ < 3; ++J_)
                for (unsigned int k = 0; k < 3; ++k)
                  for (unsigned int L = 0; L < 3; ++L)
                    (*A)[i][J_][k][L] = (i == J_ && k == L ? lambda : 0.) +
                                        (i == k && J_ == L ? mu : 0.) +
                                        (i == L && k == J_ ? mu : 0.);
        }
      else if (law == Law::st_venant_kirchhoff)
        {
          const Tensor<2, 3> E = 0.5 * (transpose(F) * F - I);
          const Tensor<2, 3> S = lambda * trace(E) * I + 2. * mu * E;
          P                    = F * S;
          if (A != nullptr)
            {
              // The same derivative as cell_response() (see there).
              const Tensor<2, 3> b = F * transpose(F);
              for (unsigned int i = 0; i < 3; ++i)
                for (unsigned int J_ = 0; J_ < 3; ++J_)
                  for (unsigned int k = 0; k < 3; ++k)
                    for (unsigned int L = 0; L < 3; ++L)
                      (*A)[i][J_][k][L] = (i == k ? S[L][J_] : 0.) +
                                          lambda * F[i][J_] * F[k][L] +
                                          mu * F[i][L] * F[k][J_] +
                                          (J_ == L ? mu * b[i][k] : 0.);
            }
        }
      else
        {
          const Tensor<2, 3> H     = transpose(invert(F)); // F^-T
          const double       log_J = std::log(J);
          P                        = mu * F + (lambda * log_J - mu) * H;
          if (A != nullptr)
            {
              const double c2 = lambda * log_J - mu;
              for (unsigned int i = 0; i < 3; ++i)
                for (unsigned int J_ = 0; J_ < 3; ++J_)
                  for (unsigned int k = 0; k < 3; ++k)
                    for (unsigned int L = 0; L < 3; ++L)
                      (*A)[i][J_][k][L] =
                        (i == k && J_ == L ? mu : 0.) +
                        lambda * H[i][J_] * H[k][L] - c2 * H[k][J_] * H[i][L];
            }
        }
      return true;
    }

    bool
    assemble(const Law             law,
             const double          lambda,
             const double          mu,
             const Mapping<3>     &mapping,
             const DoFHandler<3>  &dof_handler,
             const Quadrature<3>  &quadrature,
             const Vector<double> &u,
             Vector<double>       &forces,
             SparseMatrix<double> *tangent)
    {
      const FiniteElement<3> &fe = dof_handler.get_fe();
      FEValues<3>             fe_values(mapping,
                            fe,
                            quadrature,
                            update_gradients | update_JxW_values);
      const unsigned int      n = fe.n_dofs_per_cell();
      std::vector<types::global_dof_index> dofs(n);
      std::vector<unsigned int>            component(n);
      for (unsigned int i = 0; i < n; ++i)
        component[i] = fe.system_to_component_index(i).first;
      std::vector<double>       u_cell(n);
      std::vector<Tensor<1, 3>> grad(n);
      Vector<double>            f_cell(n);
      FullMatrix<double>        K_cell(n, n);
      Tensor<2, 3>              P;
      Tensor<4, 3>              A;
      // Rows go into the matrix with sorted columns: SparseMatrix::add then
      // merges along the row instead of searching it for every entry.
      std::vector<unsigned int>            order(n);
      std::vector<types::global_dof_index> sorted_dofs(n);
      std::vector<double>                  row(n);

      forces.reinit(u.size());
      if (tangent != nullptr)
        *tangent = 0;
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < n; ++i)
            u_cell[i] = u[dofs[i]];
          f_cell = 0;
          K_cell = 0;
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              Tensor<2, 3> F = unit_symmetric_tensor<3>();
              for (unsigned int i = 0; i < n; ++i)
                {
                  grad[i] = fe_values.shape_grad(i, q);
                  F[component[i]] += u_cell[i] * grad[i];
                }
              if (!material_response(
                    law, lambda, mu, F, P, tangent != nullptr ? &A : nullptr))
                return false;
              const double JxW = fe_values.JxW(q);
              for (unsigned int i = 0; i < n; ++i)
                f_cell[i] += (P[component[i]] * grad[i]) * JxW;
              if (tangent == nullptr)
                continue;
              // K_ij = grad_i . A[c_i][.][c_j][.] . grad_j, contracted with
              // grad_i first so that the inner loop is three products.
              for (unsigned int i = 0; i < n; ++i)
                {
                  Tensor<2, 3> G; // G[k][L] = grad_i[J] A[c_i][J][k][L]
                  for (unsigned int J_ = 0; J_ < 3; ++J_)
                    G += grad[i][J_] * A[component[i]][J_];
                  G *= JxW;
                  for (unsigned int j = 0; j < n; ++j)
                    K_cell(i, j) += G[component[j]] * grad[j];
                }
            }
          for (unsigned int i = 0; i < n; ++i)
            forces[dofs[i]] += f_cell[i];
          if (tangent == nullptr)
            continue;
          std::iota(order.begin(), order.end(), 0u);
          std::sort(order.begin(),
                    order.end(),
                    [&](unsigned int i, unsigned int j) {
                      return dofs[i] < dofs[j];
                    });
          for (unsigned int k = 0; k < n; ++k)
            sorted_dofs[k] = dofs[order[k]];
          for (unsigned int i = 0; i < n; ++i)
            {
              for (unsigned int k = 0; k < n; ++k)
                row[k] = K_cell(i, order[k]);
              tangent->add(
                dofs[i], n, sorted_dofs.data(), row.data(), false, true);
            }
        }
      return true;
    }
  } // namespace Hyperelasticity
} // namespace softface

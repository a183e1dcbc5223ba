#include <softface/error.h>
#include <softface/hyperelasticity.h>

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
      throw Error("Unknown material law '" + name + "'.");
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
      if (!(J > 0.))
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
          std::array<Tensor<1, 3>, 4> Hg;
          for (unsigned int a = 0; a < 4; ++a)
            Hg[a] = F_inverse_transpose * grad[a];
          const double c2 = lambda * log_J - mu;
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
  } // namespace Hyperelasticity
} // namespace softface

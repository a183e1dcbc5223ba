// The tissue's material laws (fe): stress and its derivative at one material
// point for linear elasticity, St. Venant-Kirchhoff and compressible
// Neo-Hooke. Every elasticity kernel contracts these; see fe/elasticity.cc.

#include <softface/core/error.h>
#include <softface/fe/material_law.h>

#include <cmath>

namespace softface
{
  namespace MaterialLaw
  {
    Law
    from_name(const std::string &text)
    {
      for (const Law law :
           {Law::linear, Law::st_venant_kirchhoff, Law::neo_hooke})
        if (name(law) == text)
          return law;
      throw Error("Unknown material law '" + text + "' (known: " + selection() +
                  ").");
    }

    std::string
    name(const Law law)
    {
      switch (law)
        {
          case Law::linear:
            return "linear";
          case Law::st_venant_kirchhoff:
            return "st venant-kirchhoff";
          case Law::neo_hooke:
            return "neo-hooke";
        }
      return "";
    }

    std::string
    selection()
    {
      return "st venant-kirchhoff|neo-hooke|linear";
    }

    bool
    first_piola_kirchhoff(const Law           law,
                          const Lame         &lame,
                          const Tensor<2, 3> &F,
                          Tensor<2, 3>       &P,
                          Tensor<4, 3>       *A)
    {
      const double lambda = lame.lambda, mu = lame.mu;
      const double J = determinant(F);
      if (!(J > 0.) && law != Law::linear)
        return false;
      const Tensor<2, 3> I = unit_symmetric_tensor<3>();

      // A's 81 entries: the products that fill every entry first, then the
      // Kronecker-delta terms on the entries they touch (no branches in the
      // loops: this runs once per cell and Newton iteration). The indices
      // are i, J, k, L of dP_iJ / dF_kL; J_ keeps J for det F.
      switch (law)
        {
          case Law::linear:
            {
              // P = lambda tr(eps) I + 2 mu eps, eps = sym(F) - I;
              // A = lambda d_iJ d_kL + mu (d_ik d_JL + d_iL d_kJ)
              const Tensor<2, 3> strain = 0.5 * (F + transpose(F)) - I;
              P = lambda * trace(strain) * I + 2. * mu * strain;
              if (A != nullptr)
                {
                  *A = 0;
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int k = 0; k < 3; ++k)
                      {
                        (*A)[i][i][k][k] += lambda;
                        (*A)[i][k][i][k] += mu;
                        (*A)[i][k][k][i] += mu;
                      }
                }
              break;
            }
          case Law::st_venant_kirchhoff:
            {
              // P = F S; A = d_ik S_JL + lambda F_iJ F_kL + mu F_iL F_kJ
              //              + mu (F F^T)_ik d_JL
              const Tensor<2, 3> E = 0.5 * (transpose(F) * F - I);
              const Tensor<2, 3> S = lambda * trace(E) * I + 2. * mu * E;
              P                    = F * S;
              if (A != nullptr)
                {
                  const Tensor<2, 3> b = F * transpose(F);
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int J_ = 0; J_ < 3; ++J_)
                      for (unsigned int k = 0; k < 3; ++k)
                        for (unsigned int L = 0; L < 3; ++L)
                          (*A)[i][J_][k][L] = lambda * F[i][J_] * F[k][L] +
                                              mu * F[i][L] * F[k][J_];
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int J_ = 0; J_ < 3; ++J_)
                      for (unsigned int L = 0; L < 3; ++L)
                        (*A)[i][J_][i][L] += S[L][J_];
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int k = 0; k < 3; ++k)
                      for (unsigned int J_ = 0; J_ < 3; ++J_)
                        (*A)[i][J_][k][J_] += mu * b[i][k];
                }
              break;
            }
          case Law::neo_hooke:
            {
              // P = mu F + (lambda ln J - mu) F^-T; with H = F^-T,
              // A = mu d_ik d_JL + lambda H_iJ H_kL - (lambda ln J - mu) H_kJ
              // H_iL
              const Tensor<2, 3> H     = transpose(invert(F));
              const double       log_J = std::log(J);
              const double       c2    = lambda * log_J - mu;
              P                        = mu * F + c2 * H;
              if (A != nullptr)
                {
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int J_ = 0; J_ < 3; ++J_)
                      for (unsigned int k = 0; k < 3; ++k)
                        for (unsigned int L = 0; L < 3; ++L)
                          (*A)[i][J_][k][L] = lambda * H[i][J_] * H[k][L] -
                                              c2 * H[k][J_] * H[i][L];
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int J_ = 0; J_ < 3; ++J_)
                      (*A)[i][J_][i][J_] += mu;
                }
              break;
            }
        }
      return true;
    }
  } // namespace MaterialLaw
} // namespace softface

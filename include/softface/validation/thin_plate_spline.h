#ifndef softface_validation_thin_plate_spline_h
#define softface_validation_thin_plate_spline_h

#include <Eigen/Dense>

#include <limits>

namespace softface
{
  namespace Validation
  {
    /// A weight that follows the temperature of an annealing: @p initial at
    /// @p t_initial, @p final at @p t_final, geometrically in between
    /// (linearly in log T when either weight is zero).
    double
    annealed_weight(double initial,
                    double final,
                    double t,
                    double t_initial,
                    double t_final);

    /**
     * The thin-plate spline f(x) = sum_j w_j phi(|x - c_j|) + [1 x] a over
     * control points c_j, with phi(r) = -r, the kernel of the 3D thin
     * plate, fitted by regularised least squares to one goal position per
     * point of a fixed point set (the non-rigid part of TPS-RPM). With w
     * orthogonal to the affine functions at the control points (w = Q2 g,
     * Q2 a basis of that complement), w^T Phi w = g^T Q2^T Phi Q2 g >= 0 is
     * the bending energy int |D^2 f|^2 / (8 pi). The design matrix over the
     * points never changes: its Gram matrix is formed once, and a fit costs
     * two products with the design matrix and a small solve (factorised
     * again only when the weights change).
     *
     * Memory: the N x (K + 4) design matrix (N points, K control points).
     * Starts as the identity map.
     */
    class ThinPlateSpline
    {
    public:
      ThinPlateSpline(const Eigen::MatrixX3d &points,
                      const Eigen::MatrixX3d &control);

      /// Fit to @p goal (one row per point) with weight @p lambda on the
      /// bending energy and @p affine_lambda on |A - I|^2 (A the linear
      /// part); the misfit is the mean squared distance.
      void
      fit(const Eigen::MatrixX3d &goal, double lambda, double affine_lambda);

      /// The points moved by the current fit.
      Eigen::MatrixX3d
      warped() const;

      /// Other points moved by the current fit.
      Eigen::MatrixX3d
      warp(const Eigen::MatrixX3d &at) const;

    private:
      void
      factorise(double lambda, double affine_lambda);

      /// phi(|x_i - c_j|) Q2 for the rows x_i of @p at.
      Eigen::MatrixXd
      bending_design(const Eigen::MatrixX3d &at) const;

      Eigen::MatrixX3d             control;
      Eigen::MatrixXd              q2;
      Eigen::Index                 n_unknowns = 0;
      Eigen::MatrixXd              bending;
      Eigen::MatrixXd              design;
      Eigen::MatrixXd              gram;
      Eigen::LDLT<Eigen::MatrixXd> factorisation;
      double factorised_lambda = std::numeric_limits<double>::quiet_NaN();
      double factorised_affine_lambda =
        std::numeric_limits<double>::quiet_NaN();
      Eigen::MatrixX3d coefficients;
    };
  } // namespace Validation
} // namespace softface

#endif

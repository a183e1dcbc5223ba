// The thin-plate spline of TPS-RPM (validation; Mollemans et al. 2007,
// Sec. 3.5.1). Eigen only.

#include <softface/core/error.h>
#include <softface/validation/thin_plate_spline.h>

#include <algorithm>
#include <cmath>

namespace softface
{
  namespace Validation
  {
    namespace
    {
      /**
       * An orthogonal Q whose first columns span those of @p a (n x m, n >=
       * m or not), by Householder reflections: its last n - m columns are an
       * orthonormal basis of the vectors orthogonal to them. (Written here, not
       * Eigen's: 3.4's HouseholderQR draws a false -Wmaybe-uninitialized from
       * GCC 12.)
       */
      Eigen::MatrixXd
      orthogonal_complement(Eigen::MatrixXd a)
      {
        const Eigen::Index n           = a.rows();
        const Eigen::Index m           = std::min(a.rows(), a.cols());
        Eigen::MatrixXd    reflections = Eigen::MatrixXd::Zero(n, m);
        for (Eigen::Index i = 0; i < m; ++i)
          {
            // The reflection I - 2 v v^T taking a(i:, i) to a multiple of
            // e_i; none for a zero column (rank-deficient a).
            Eigen::VectorXd v    = a.col(i).tail(n - i);
            const double    norm = v.norm();
            if (norm == 0.)
              continue;
            v[0] += v[0] < 0. ? -norm : norm;
            v.normalize();
            a.bottomRows(n - i) -=
              2. * v * (v.transpose() * a.bottomRows(n - i));
            reflections.col(i).tail(n - i) = v;
          }
        // Q = H_0 H_1 ... H_{m-1} I, the last reflection applied first.
        Eigen::MatrixXd q = Eigen::MatrixXd::Identity(n, n);
        for (Eigen::Index i = m - 1; i >= 0; --i)
          {
            const Eigen::VectorXd v = reflections.col(i).tail(n - i);
            q.bottomRows(n - i) -=
              2. * v * (v.transpose() * q.bottomRows(n - i));
          }
        return q;
      }

      /// phi(|x_i - c_j|) = -|x_i - c_j| for the rows of @p at and @p control.
      Eigen::MatrixXd
      kernel(const Eigen::MatrixX3d &at, const Eigen::MatrixX3d &control)
      {
        Eigen::MatrixXd values(at.rows(), control.rows());
        for (Eigen::Index j = 0; j < control.rows(); ++j)
          values.col(j) = -(at.rowwise() - control.row(j)).rowwise().norm();
        return values;
      }
    } // namespace


    double
    annealed_weight(const double initial,
                    const double final,
                    const double t,
                    const double t_initial,
                    const double t_final)
    {
      const double s = t_initial > t_final ? std::log(t_initial / t) /
                                               std::log(t_initial / t_final) :
                                             1.;
      if (initial > 0. && final > 0.)
        return initial * std::pow(final / initial, s);
      return initial + s * (final - initial);
    }


    ThinPlateSpline::ThinPlateSpline(const Eigen::MatrixX3d &points,
                                     const Eigen::MatrixX3d &control)
        : control(control)
    {
      const Eigen::Index n_control = control.rows();
      const Eigen::Index n_bending = std::max<Eigen::Index>(0, n_control - 4);
      n_unknowns                   = n_bending + 4;

      Eigen::MatrixXd affine_at_control(n_control, 4);
      affine_at_control.col(0).setOnes();
      affine_at_control.rightCols(3) = control;
      q2      = orthogonal_complement(affine_at_control).rightCols(n_bending);
      bending = q2.transpose() * kernel(control, control) * q2;

      design.resize(points.rows(), n_unknowns);
      design.leftCols(n_bending) = bending_design(points);
      design.col(n_bending).setOnes();
      design.rightCols(3) = points;

      // The data term is the mean squared misfit, so that lambda does not
      // depend on the number of points.
      gram.setZero(n_unknowns, n_unknowns);
      gram.selfadjointView<Eigen::Lower>().rankUpdate(design.transpose(),
                                                      1. / points.rows());
      coefficients.setZero(n_unknowns, 3);
      coefficients.bottomRows(3).setIdentity();
    }


    Eigen::MatrixXd
    ThinPlateSpline::bending_design(const Eigen::MatrixX3d &at) const
    {
      // In blocks of rows: no N x K kernel matrix besides the result.
      const Eigen::Index n_bending = q2.cols();
      const Eigen::Index block     = 1024;
      Eigen::MatrixXd    result(at.rows(), n_bending);
      for (Eigen::Index start = 0; start < at.rows(); start += block)
        {
          const Eigen::Index rows = std::min(block, at.rows() - start);
          result.middleRows(start, rows) =
            kernel(at.middleRows(start, rows), control) * q2;
        }
      return result;
    }


    void
    ThinPlateSpline::fit(const Eigen::MatrixX3d &goal,
                         const double            lambda,
                         const double            affine_lambda)
    {
      if (lambda != factorised_lambda ||
          affine_lambda != factorised_affine_lambda)
        factorise(lambda, affine_lambda);
      Eigen::MatrixX3d rhs =
        design.transpose() * goal / static_cast<double>(design.rows());
      rhs.bottomRows(3) += affine_lambda * Eigen::Matrix3d::Identity();
      coefficients = factorisation.solve(rhs);
    }


    Eigen::MatrixX3d
    ThinPlateSpline::warped() const
    {
      return design * coefficients;
    }


    Eigen::MatrixX3d
    ThinPlateSpline::warp(const Eigen::MatrixX3d &at) const
    {
      // In blocks, so that memory stays at one block's kernel.
      const Eigen::Index n_bending = q2.cols();
      const Eigen::Index block     = 4096;
      Eigen::MatrixX3d   result(at.rows(), 3);
      for (Eigen::Index start = 0; start < at.rows(); start += block)
        {
          const Eigen::Index rows = std::min(block, at.rows() - start);
          const auto         part = at.middleRows(start, rows);
          result.middleRows(start, rows) =
            bending_design(part) * coefficients.topRows(n_bending) +
            Eigen::VectorXd::Ones(rows) * coefficients.row(n_bending) +
            part * coefficients.bottomRows(3);
        }
      return result;
    }


    void
    ThinPlateSpline::factorise(const double lambda, const double affine_lambda)
    {
      const Eigen::Index n_bending = n_unknowns - 4;
      Eigen::MatrixXd    matrix    = gram;
      matrix.topLeftCorner(n_bending, n_bending) += lambda * bending;
      matrix.bottomRightCorner(3, 3).diagonal().array() += affine_lambda;
      // A ridge relative to the diagonal keeps degenerate input (coplanar
      // points, no affine weight) solvable.
      matrix.diagonal().array() += 1e-12 * matrix.diagonal().mean();
      factorisation.compute(matrix);
      if (factorisation.info() != Eigen::Success)
        throw Error("TPS-RPM: the thin-plate spline system is singular; "
                    "raise lambda or the affine weight.");
      factorised_lambda        = lambda;
      factorised_affine_lambda = affine_lambda;
    }
  } // namespace Validation
} // namespace softface

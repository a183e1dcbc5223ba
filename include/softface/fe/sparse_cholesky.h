#ifndef softface_sparse_cholesky_h
#define softface_sparse_cholesky_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <cstddef>

namespace softface
{
  using namespace dealii;

  /**
   * A sparse Cholesky factorisation A = L L^T of a symmetric positive definite
   * matrix (SuiteSparse CHOLMOD, supernodal, fill-reducing ordering chosen
   * by CHOLMOD). The stiffness with eliminated join DoFs is SPD, so this does
   * half the work of a general LU and two triangular solves per right-hand
   * side; factorise once, solve for any number of plannings.
   */
  class SparseCholesky
  {
  public:
    SparseCholesky();
    ~SparseCholesky();
    SparseCholesky(const SparseCholesky &) = delete;
    SparseCholesky &
    operator=(const SparseCholesky &) = delete;

    /// Factorise @p matrix (only its upper triangle is read).
    void
    factorize(const SparseMatrix<double> &matrix);

    /**
     * Factorise a matrix with the same pattern as the last one again,
     * reusing the ordering and symbolic analysis. Returns false (instead of
     * throwing) if the matrix is not positive definite.
     */
    bool
    refactorize(const SparseMatrix<double> &matrix);

    /// x = A^-1 b
    void
    solve(const Vector<double> &b, Vector<double> &x) const;

    /// Entries of L (fill-in included).
    std::size_t
    n_factor_entries() const;

    void
    clear();

  private:
    // CHOLMOD's types stay out of this header.
    void       *common;
    void       *factor;
    std::size_t n_rows    = 0;
    std::size_t n_entries = 0;
  };
} // namespace softface

#endif

// Sparse Cholesky factorisation by SuiteSparse CHOLMOD (fe): the direct
// solver of the linear solver helper, its ordering and symbolic analysis
// reused when only the matrix values change.

#include <softface/core/error.h>
#include <softface/fe/sparse_cholesky.h>

#include <suitesparse/cholmod.h>

#include <cstring>
#include <string>

namespace softface
{
  namespace
  {
    cholmod_common *
    as_common(void *p)
    {
      return static_cast<cholmod_common *>(p);
    }
  } // namespace

  SparseCholesky::SparseCholesky()
      : common(new cholmod_common)
      , factor(nullptr)
  {
    cholmod_start(as_common(common));
    as_common(common)->print = 0;
  }

  SparseCholesky::~SparseCholesky()
  {
    clear();
    cholmod_finish(as_common(common));
    delete as_common(common);
  }

  void
  SparseCholesky::clear()
  {
    if (factor != nullptr)
      {
        cholmod_factor *L = static_cast<cholmod_factor *>(factor);
        cholmod_free_factor(&L, as_common(common));
        factor = nullptr;
      }
  }

  void
  SparseCholesky::factorize(const SparseMatrix<double> &matrix)
  {
    clear();
    if (!refactorize(matrix))
      throw Error("direct solver: the Cholesky factorisation failed (CHOLMOD "
                  "status " +
                  std::to_string(as_common(common)->status) +
                  "); the matrix is not positive definite or memory ran out.");
  }

  bool
  SparseCholesky::refactorize(const SparseMatrix<double> &matrix)
  {
    const SparsityPattern &pattern = matrix.get_sparsity_pattern();
    const std::size_t      n       = matrix.m();

    // A symmetric matrix's upper triangle in rows (CSR) is its lower
    // triangle in columns (CSC), which is what CHOLMOD takes (stype = -1).
    // deal.II stores the diagonal first in each row and the other columns
    // ascending, so the row indices of every CSC column come out sorted.
    std::size_t n_lower = 0;
    for (std::size_t row = 0; row < n; ++row)
      for (auto entry = pattern.begin(row); entry != pattern.end(row); ++entry)
        if (entry->column() >= row)
          ++n_lower;

    cholmod_sparse *A = cholmod_allocate_sparse(n,
                                                n,
                                                n_lower,
                                                /*sorted*/ 1,
                                                /*packed*/ 1,
                                                /*stype*/ -1,
                                                CHOLMOD_REAL,
                                                as_common(common));
    if (A == nullptr)
      throw Error("direct solver: CHOLMOD could not allocate the matrix (" +
                  std::to_string(n_lower) + " entries).");
    auto       *column_start = static_cast<int *>(A->p);
    auto       *row_index    = static_cast<int *>(A->i);
    auto       *value        = static_cast<double *>(A->x);
    std::size_t k            = 0;
    for (std::size_t row = 0; row < n; ++row)
      {
        column_start[row] = k;
        for (auto entry = matrix.begin(row); entry != matrix.end(row); ++entry)
          if (entry->column() >= row)
            {
              row_index[k] = entry->column();
              value[k]     = entry->value();
              ++k;
            }
      }
    column_start[n] = k;

    // The fill-reducing ordering and symbolic factor depend only on the
    // pattern: computed once, reused by every later factorisation (Newton).
    if (factor == nullptr || n != n_rows || n_lower != n_entries)
      {
        clear();
        factor    = cholmod_analyze(A, as_common(common));
        n_rows    = n;
        n_entries = n_lower;
      }
    const bool ok = (factor != nullptr) &&
                    cholmod_factorize(A,
                                      static_cast<cholmod_factor *>(factor),
                                      as_common(common)) &&
                    as_common(common)->status == CHOLMOD_OK;
    cholmod_free_sparse(&A, as_common(common));
    return ok;
  }

  void
  SparseCholesky::solve(const Vector<double> &b, Vector<double> &x) const
  {
    Assert(factor != nullptr, ExcMessage("factorize() first"));
    cholmod_dense B;
    std::memset(&B, 0, sizeof(B));
    B.nrow           = b.size();
    B.ncol           = 1;
    B.nzmax          = b.size();
    B.d              = b.size();
    B.x              = const_cast<double *>(b.begin());
    B.xtype          = CHOLMOD_REAL;
    B.dtype          = CHOLMOD_DOUBLE;
    cholmod_dense *X = cholmod_solve(CHOLMOD_A,
                                     static_cast<cholmod_factor *>(factor),
                                     &B,
                                     as_common(common));
    if (X == nullptr)
      throw Error("direct solver: CHOLMOD's solve failed.");
    x.reinit(b.size(), true);
    std::memcpy(x.begin(), X->x, sizeof(double) * b.size());
    cholmod_free_dense(&X, as_common(common));
  }

  std::size_t
  SparseCholesky::n_factor_entries() const
  {
    if (factor == nullptr)
      return 0;
    const auto *L = static_cast<const cholmod_factor *>(factor);
    return L->is_super ? L->xsize : L->nzmax;
  }
} // namespace softface

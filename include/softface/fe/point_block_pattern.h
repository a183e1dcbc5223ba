#ifndef softface_fe_point_block_pattern_h
#define softface_fe_point_block_pattern_h

#include <deal.II/lac/sparsity_pattern.h>

#include <softface/core/point_mesh.h>

#include <array>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * The sparsity of the shared P1 layout when its DoFs are point blocks
   * (3p, 3p+1, 3p+2): each DoF couples with every component of its own
   * point and of every point it shares a tetrahedron with. That is the
   * pattern DoFTools::make_sparsity_pattern() makes, here made from the
   * points' neighbour lists in one pass, with each row's length known
   * (deal.II inserts every cell's 144 entries into sorted rows, and on a
   * gmsh mesh its insertions take twice as long per cell as on the
   * generated cube, whose rows come nearly in order); and the place of any
   * entry in the value array of a SparseMatrix on it, found without
   * searching the row (a merge along the row mispredicts its branches on
   * an irregular mesh).
   *
   * The same work per cell on any mesh, whatever its cell order.
   */
  class PointBlockPattern
  {
  public:
    /// On the points and neighbours of @p points (referred to, not copied).
    explicit PointBlockPattern(const PointMesh &points);
    PointBlockPattern(PointMesh &&) = delete;

    /// Entries of the pattern (9 per pair of neighbours and per point).
    std::size_t
    n_entries() const;

    /// The pattern (3 x the points rows, square, compressed).
    void
    make_sparsity(SparsityPattern &sparsity) const;

    /**
     * Where the entries of cell @p cell (the mesh's cells in order, whose
     * points p are PointMesh::tetrahedra[cell]) live in the value array of
     * a SparseMatrix on make_sparsity()'s pattern: entry (3 p[a] + i,
     * 3 p[b] + j) at @p positions[12 (3a + i) + 3b + j].
     */
    void
    cell_positions(const unsigned int cell, unsigned int *positions) const;

  private:
    const PointMesh &points;
  };
} // namespace softface

#endif

#ifndef softface_release_h
#define softface_release_h

#include <vector>

namespace softface
{
  /**
   * Give a vector's memory back. `v = {}` does not: it assigns an empty
   * initializer list, which empties the vector and keeps its capacity (the
   * "freed" support points of a quadratic layout stayed on every rank).
   */
  template <typename T>
  void
  release(std::vector<T> &v)
  {
    std::vector<T>().swap(v);
  }
} // namespace softface

#endif

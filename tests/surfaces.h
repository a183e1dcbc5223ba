#ifndef softface_tests_surfaces_h
#define softface_tests_surfaces_h

// Triangle surfaces that the mapping and validation tests build in code.

#include <softface/mapping/triangle_search.h>

#include <map>
#include <utility>

namespace softface_tests
{
  using namespace softface;

  /// The unit sphere as an icosahedron refined @p levels times (10 4^levels
  /// + 2 points), wound outwards: closed and manifold.
  inline SurfaceMapping::Surface
  unit_icosphere(const unsigned int levels)
  {
    SurfaceMapping::Surface s;
    const double            t = (1. + std::sqrt(5.)) / 2.;
    for (const auto &p : std::vector<Point<3>>{{-1, t, 0},
                                               {1, t, 0},
                                               {-1, -t, 0},
                                               {1, -t, 0},
                                               {0, -1, t},
                                               {0, 1, t},
                                               {0, -1, -t},
                                               {0, 1, -t},
                                               {t, 0, -1},
                                               {t, 0, 1},
                                               {-t, 0, -1},
                                               {-t, 0, 1}})
      s.points.push_back(p / p.norm());
    s.triangles = {{{0, 11, 5}},  {{0, 5, 1}},  {{0, 1, 7}},  {{0, 7, 10}},
                   {{0, 10, 11}}, {{1, 5, 9}},  {{5, 11, 4}}, {{11, 10, 2}},
                   {{10, 7, 6}},  {{7, 1, 8}},  {{3, 9, 4}},  {{3, 4, 2}},
                   {{3, 2, 6}},   {{3, 6, 8}},  {{3, 8, 9}},  {{4, 9, 5}},
                   {{2, 4, 11}},  {{6, 2, 10}}, {{8, 6, 7}},  {{9, 8, 1}}};
    for (unsigned int level = 0; level < levels; ++level)
      {
        std::map<std::pair<unsigned int, unsigned int>, unsigned int> middle;
        const auto mid = [&](const unsigned int a, const unsigned int b) {
          const auto key = std::minmax(a, b);
          const auto it  = middle.find(key);
          if (it != middle.end())
            return it->second;
          const Point<3> m = (s.points[a] + s.points[b]) / 2.;
          s.points.push_back(m / m.norm());
          return middle[key] = s.points.size() - 1;
        };
        std::vector<std::array<unsigned int, 3>> finer;
        for (const auto &tri : s.triangles)
          {
            const unsigned int a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]),
                               c = mid(tri[2], tri[0]);
            finer.push_back({{tri[0], a, c}});
            finer.push_back({{tri[1], b, a}});
            finer.push_back({{tri[2], c, b}});
            finer.push_back({{a, b, c}});
          }
        s.triangles.swap(finer);
      }
    return s;
  }

  /// @p surface with every point mapped by @p f.
  template <typename Function>
  inline SurfaceMapping::Surface
  transformed(SurfaceMapping::Surface surface, const Function &f)
  {
    for (auto &p : surface.points)
      p = f(p);
    return surface;
  }
} // namespace softface_tests

#endif

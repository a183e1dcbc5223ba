// A read mesh's checks and locality order take faster paths than the
// library calls they replace: the Hilbert keys are computed in
// pieces on the threads after deal.II's own mapping to integers, by a
// transform without branches on the bits (deal.II's algorithm), and cell
// and face lists are sorted by a counting sort on their first point. Both
// must give exactly what the library gives. Independent truth: deal.II's
// Utilities::inverse_Hilbert_space_filling_curve() with pack_integers(), and
// std::sort.

#include <deal.II/base/utilities.h>

#include <softface/core/cell_order.h>
#include <softface/core/threads.h>

#include "tests.h"

#include <array>
#include <random>

using namespace softface;

namespace
{
  long long
  keys_unlike_dealii(const std::vector<Point<3>> &points, const int bits)
  {
    const auto keys = Mesh::hilbert_keys(points, bits);
    const auto curve =
      Utilities::inverse_Hilbert_space_filling_curve(points, bits);
    long long unlike = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
      unlike += (keys[i] != Utilities::pack_integers<3>(curve[i], bits));
    return unlike;
  }
} // namespace

SOFTFACE_TEST(cell_order_fast_paths)
{
  std::mt19937                           random(7);
  std::uniform_real_distribution<double> coordinate(-40., 95.);

  // More points than one piece (16384), so that the pieces' seams count;
  // a flat set goes through deal.II's own treatment of flat axes.
  std::vector<Point<3>> points(40000), flat(3000);
  for (auto &p : points)
    p = Point<3>(coordinate(random), coordinate(random), coordinate(random));
  for (auto &p : flat)
    p = Point<3>(coordinate(random), 12.5, coordinate(random));
  for (const unsigned int threads : {1u, 3u})
    {
      softface::Threads::set_limit(threads);
      const std::string on =
        threads == 1 ? " (one thread)" : " (three threads asked)";
      softface_tests::check_equal(
        "Hilbert keys unlike deal.II's, 40000 points" + on,
        keys_unlike_dealii(points, 21),
        0);
      softface_tests::check_equal(
        "Hilbert keys unlike deal.II's, 3000 points in a plane" + on,
        keys_unlike_dealii(flat, 21),
        0);
    }
  softface::Threads::set_limit(1);
  // Fewer bits per direction: the transform's loops and the interleaving
  // at every depth (the mesh order takes 21).
  for (const int bits : {1, 2, 7, 16})
    softface_tests::check_equal(
      "Hilbert keys unlike deal.II's, 40000 points, " + std::to_string(bits) +
        " bits",
      keys_unlike_dealii(points, bits),
      0);

  // Triangles (sorted points) with the cell they came from; small
  // vertex numbers make many equal triangles, whose order the cell decides.
  std::uniform_int_distribution<unsigned int> vertex(0, 499);
  std::vector<std::pair<std::array<unsigned int, 3>, std::size_t>> faces(60000);
  for (std::size_t f = 0; f < faces.size(); ++f)
    {
      auto &t = faces[f].first;
      for (auto &v : t)
        v = vertex(random);
      std::sort(t.begin(), t.end());
      faces[f].second = f % 7919;
    }
  auto by_std_sort = faces;
  std::sort(by_std_sort.begin(), by_std_sort.end());
  Mesh::sort_by_first_point(faces, 500, [](const auto &face) {
    return face.first[0];
  });
  long long misplaced = 0;
  for (std::size_t f = 0; f < faces.size(); ++f)
    misplaced += (faces[f] != by_std_sort[f]);
  softface_tests::check_equal("faces out of std::sort's order", misplaced, 0);
}

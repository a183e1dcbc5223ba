#ifndef softface_tests_h
#define softface_tests_h

// A small tests.h of our own (deal.II 9.4 does not install one). Every
// tests/<name>.cc defines one test with SOFTFACE_TEST(name); the driver in
// tests/main.cc runs it with deallog going to stdout, and ctest compares that
// with tests/<name>.output.

#include <deal.II/base/logstream.h>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

namespace softface_tests
{
  using namespace dealii;

  bool
  register_test(const std::string &name, void (*function)());

  /// A failed check ends the test with a non-zero exit, naming the check.
  inline void
  check(const bool condition, const std::string &what)
  {
    deallog << what << ": " << (condition ? "yes" : "NO") << std::endl;
    if (!condition)
      throw std::runtime_error("check failed: " + what);
  }

  /// A number rounded to @p digits significant digits (stable across runs
  /// as long as the value is accurate to more than that).
  inline std::string
  rounded(const double value, const unsigned int digits = 4)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << (std::abs(value) < 1e-300 ? 0. : value);
    return s.str();
  }

  /// A file in the tests' source folder (tests run in the build folder, so
  /// that what they write stays out of the source tree).
  inline std::string
  source_file(const std::string &name)
  {
    return std::string(SOFTFACE_TESTS_SOURCE_DIR) + "/" + name;
  }
} // namespace softface_tests

#define SOFTFACE_TEST(name)                                      \
  static void       softface_test_##name();                      \
  static const bool softface_test_registered_##name =            \
    softface_tests::register_test(#name, &softface_test_##name); \
  static void softface_test_##name()

#endif

#ifndef softface_tests_h
#define softface_tests_h

// softface's own small tests.h (deal.II 9.4 does not install one). Every
// tests/<name>.cc defines one test with SOFTFACE_TEST(name); the driver in
// tests/main.cc runs it with deallog going to stdout, and ctest compares that
// with tests/<name>.output by numdiff (absolute 1e-10, relative 1e-8).
//
// Tests print the quantities they check, at a precision that is stable from
// run to run (deal.II style), so that numdiff sees any drift; a quantity
// that must stay within a bound is printed with the bound and also ends the
// test with an error when it leaves it. A mesh made by CGAL's Mesh_3 is the
// same from run to run with the same libraries, so its counts are printed
// too (another CGAL or C library may change them: re-bless then).

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

  /// A number rounded to @p digits significant digits.
  inline std::string
  rounded(const double value, const unsigned int digits = 3)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << (std::abs(value) < 1e-300 ? 0. : value);
    return s.str();
  }

  /// "what: value".
  inline void
  print(const std::string &what,
        const double       value,
        const unsigned int digits = 3)
  {
    deallog << what << ": " << rounded(value, digits) << std::endl;
  }

  /// "what: value (<= bound)"; the test fails if value > bound or is NaN.
  /// Three digits show a change of 1 %; numdiff's absolute floor (1e-10)
  /// hides changes of values below it, so an error that should stay at
  /// round-off gets a bound close to it.
  inline void
  check_below(const std::string &what,
              const double       value,
              const double       bound,
              const unsigned int digits = 3)
  {
    deallog << what << ": " << rounded(value, digits)
            << " (<= " << rounded(bound, 3) << ")" << std::endl;
    if (!(value <= bound))
      throw std::runtime_error(what + " = " + rounded(value, 6) + " exceeds " +
                               rounded(bound, 6));
  }

  /// "what: value (>= bound)"; the test fails if value < bound or is NaN.
  inline void
  check_above(const std::string &what,
              const double       value,
              const double       bound,
              const unsigned int digits = 3)
  {
    deallog << what << ": " << rounded(value, digits)
            << " (>= " << rounded(bound, 3) << ")" << std::endl;
    if (!(value >= bound))
      throw std::runtime_error(what + " = " + rounded(value, 6) + " is below " +
                               rounded(bound, 6));
  }

  /// "what: value"; the test fails unless value == expected (counts).
  inline void
  check_equal(const std::string &what,
              const long long    value,
              const long long    expected)
  {
    deallog << what << ": " << value << std::endl;
    if (value != expected)
      throw std::runtime_error(what + " = " + std::to_string(value) +
                               ", expected " + std::to_string(expected));
  }

  /// "what: value (in [low, high])"; the test fails if value is outside or
  /// NaN.
  inline void
  check_within(const std::string &what,
               const double       value,
               const double       low,
               const double       high,
               const unsigned int digits = 3)
  {
    deallog << what << ": " << rounded(value, digits) << " (in ["
            << rounded(low, 3) << ", " << rounded(high, 3) << "])" << std::endl;
    if (!(value >= low && value <= high))
      throw std::runtime_error(what + " = " + rounded(value, 6) +
                               " is outside [" + rounded(low, 6) + ", " +
                               rounded(high, 6) + "]");
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

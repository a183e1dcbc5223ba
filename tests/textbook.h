#ifndef softface_tests_textbook_h
#define softface_tests_textbook_h

// Formulas the tests write down from the textbook, so that a test of a model
// does not take them from the code it tests.

namespace softface_tests
{
  /**
   * Lame's coefficients from Young's modulus @p E and Poisson's ratio
   * @p nu, written here from the textbook (lambda = E nu / ((1 + nu)
   * (1 - 2 nu)), mu = E / (2 (1 + nu))) so that a test of a model does not
   * take them from the code it tests.
   */
  struct TextbookLame
  {
    double lambda, mu;
  };
  inline TextbookLame
  textbook_lame(const double E, const double nu)
  {
    return {E * nu / ((1. + nu) * (1. - 2. * nu)), E / (2. * (1. + nu))};
  }

} // namespace softface_tests

#endif

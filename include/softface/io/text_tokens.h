#ifndef softface_io_text_tokens_h
#define softface_io_text_tokens_h

#include <cstdint>
#include <string>
#include <string_view>

namespace softface
{
  namespace Mesh
  {
    /**
     * The whitespace-separated words of a text mesh file held in memory,
     * read one at a time with the line each came from, so that every error
     * names the file and line. Numbers are parsed strictly (a word that is
     * not entirely a number is an error, never a zero), and a declared count
     * is checked against the bytes the file has left before anything is
     * allocated for it: a small file can never ask for gigabytes. What a
     * word is meant to be (@p what) is a view: a message is only built when
     * reading fails, never per word.
     */
    class TextTokens
    {
    public:
      /// Read the whole file; throws softface::Error if it cannot.
      explicit TextTokens(const std::string &filename);

      /// The next word; throws "ends early" (naming @p what) at the end.
      std::string_view
      word(std::string_view what);

      /// Whether the next word exists (without consuming it).
      bool
      at_end();

      /// The next word as a whole number in [minimum, maximum].
      std::int64_t
      integer(std::string_view what,
              std::int64_t     minimum = INT64_MIN,
              std::int64_t     maximum = INT64_MAX);

      /// The next word as a finite real number.
      double
      real(std::string_view what);

      /// The next word as a point's coordinate: a real number no larger in
      /// magnitude than Mesh::largest_coordinate.
      double
      coordinate(std::string_view what);

      /// The next word must be @p expected.
      void
      expect(const std::string &expected);

      /// The rest of the current line (after the last word read), trimmed.
      std::string
      rest_of_line();

      /// The next whole line, trimmed (for headers).
      std::string
      line_text(std::string_view what);

      /**
       * A count of items that take at least @p words_per_item words each:
       * refused if the file's remaining bytes cannot hold that many.
       */
      std::uint64_t
      count(std::string_view what, const std::uint64_t words_per_item);

      /// How many more words the file could hold at most.
      std::uint64_t
      count_limit() const
      {
        return (text.size() - position) / 2;
      }

      /// Whether the next word is @p word (without consuming it).
      bool
      next_is(const std::string &word);

      /// Skip whole lines up to and including the next empty one.
      void
      skip_to_empty_line();

      /// Skip words up to and including @p end_marker (an unknown section).
      void
      skip_to(const std::string &end_marker);

      /// The line of the last word read (1-based).
      std::size_t
      line() const
      {
        return last_line;
      }

      /// "file:line: " for messages about the last word read.
      std::string
      where() const;

      /// An error at the last word read.
      [[noreturn]] void
      fail(const std::string &message) const;

    private:
      std::string filename;
      std::string text;
      std::size_t position     = 0;
      std::size_t current_line = 1;
      std::size_t last_line    = 1;

      void
      skip_space();
    };
  } // namespace Mesh
} // namespace softface

#endif

#pragma once
// A tiny CSV table builder and reader for the run folder (summary.csv, profiles, spectra)
// and for the user's own tables (surveys, hardness periods).
// Written: comma separated, first line is the header, '\n' line ends, fields quoted with '"'
// only when they contain a comma, a quote or a line end (RFC 4180; a quote inside a quoted
// field is doubled). Numbers are written with std::snprintf in the C locale, so '.' is
// always the decimal point.
// Read: the same, and also as spreadsheets save CSV: a UTF-8 byte-order mark is skipped,
// '\r\n' line ends are accepted, and a file whose header has ';' and no ',' is read as
// ';'-separated (European Excel), where a number may have a decimal comma ("12,5").
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

namespace millwear::io {

struct CsvOptions {
  // Significant digits for doubles (%.<n>g). 10 digits keeps files readable and is far
  // finer than any quantity we write (areas in mm^2, powers in kW).
  int significant_digits = 10;
  // Exact round trip: write doubles with %.17g so strtod gives back the same bits.
  // Use for files that a resumed run reads back as state.
  bool exact = false;
};

// One cell: text, a floating-point number or an integer (integers are never rounded).
struct CsvCell {
  std::variant<std::string, double, long long> value;
  CsvCell(std::string s) : value(std::move(s)) {}
  CsvCell(const char* s) : value(std::string(s)) {}
  CsvCell(double d) : value(d) {}
  CsvCell(float d) : value(static_cast<double>(d)) {}
  CsvCell(int i) : value(static_cast<long long>(i)) {}
  CsvCell(long i) : value(static_cast<long long>(i)) {}
  CsvCell(long long i) : value(i) {}
  CsvCell(unsigned i) : value(static_cast<long long>(i)) {}
  CsvCell(unsigned long i) : value(static_cast<long long>(i)) {}
  CsvCell(unsigned long long i) : value(static_cast<long long>(i)) {}
  CsvCell(bool b) : value(static_cast<long long>(b ? 1 : 0)) {}
};

// Formats a double with `digits` significant digits (%.<digits>g). Non-finite values are
// written as nan, inf, -inf (strtod and gnuplot read them back).
std::string format_number(double v, int digits = 10);
// Formats a double so that strtod returns the same value (%.17g).
std::string format_exact(double v);
// The fewest significant digits that strtod reads back as the same value: 0.7 as "0.7",
// 0.7000000000000001 as itself (two values never print alike); from 1e-4 to 1e16 without an
// exponent (20 as "20", not "2e+01").
std::string format_shortest(double v);
// Formats a double for a table people read, with a printf format of one double ("%.2f");
// a value that is not finite is written "-".
std::string format_for_table(double v, const char* format);
// Quotes a text field if it needs it (comma, quote, CR or LF inside).
std::string quote_field(const std::string& s);

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> header, CsvOptions options = {});

  // Appends a row. Throws std::invalid_argument if its length differs from the header's
  // (a programming error, not a user's).
  CsvTable& add_row(std::vector<CsvCell> row);

  const std::vector<std::string>& header() const { return header_; }
  std::size_t row_count() const { return rows_.size(); }

  // The whole table as CSV text, header first, each line ending in '\n'.
  std::string str() const;
  // Writes str() to `path` atomically (see write_file_atomic). Throws RunError.
  void write(const std::string& path) const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;  // already formatted
  CsvOptions options_;
};

// A CSV file as read: header, rows of text fields, and where each row was in the file,
// so that errors found later (a bad number in row 7) can name the line.
// The UTF-8 byte-order mark some programs put at the start of a text file.
constexpr const char kUtf8Bom[] = "\xEF\xBB\xBF";

struct CsvData {
  std::string path;                     // as given to read_csv, used in error messages
  char separator = ',';                 // ',' or ';' (found from the header)
  std::vector<std::string> header;      // the column names without the blanks around them
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> row_line;    // 1-based line number of each row in the file
  std::size_t header_line = 1;          // 1-based line number of the header (after blank lines)
  // A ';' file's first number written with a decimal comma ("385,5") and its line; 0: none.
  // In such a file a number like "1.000" is a thousands separator, not a decimal point.
  std::size_t decimal_comma_line = 0;
  std::string decimal_comma_example;

  std::size_t row_count() const { return rows.size(); }
  bool has_column(const std::string& name) const;
  // Index of a header column. Throws InputError(path, "line H", "a column named NAME"), H the
  // header's line.
  std::size_t column(const std::string& name) const;
  const std::string& text(std::size_t row, std::size_t col) const;
  // The field as a double (strtod, whole field, surrounding spaces allowed; nan/inf
  // accepted, hexadecimal not; in a ';' file one ',' is the decimal separator, and where the
  // file writes decimal commas, points in groups of three digits, "1.000", are refused as
  // thousands separators).
  // Throws InputError(path, "line N", "a number in column NAME, found 'X'").
  double number(std::size_t row, std::size_t col) const;
  double number(std::size_t row, const std::string& col) const { return number(row, column(col)); }
  // A whole column as numbers (same errors as number()).
  std::vector<double> numbers(const std::string& col) const;
  // As number() and numbers(), nan and inf refused too: for files that never hold them (the
  // stage files millwear writes and reads back).
  double finite_number(std::size_t row, std::size_t col) const;
  std::vector<double> finite_numbers(const std::string& col) const;
  std::vector<std::string> texts(const std::string& col) const;
};

// Parses CSV text; `name` is used as the file in error messages. A leading byte-order
// mark is skipped; the separator is found from the header (see above).
// Throws InputError(name, "line N", ...) on: no header, a row with a different number of
// fields than the header, an unterminated quoted field, UTF-16 text. Blank lines are
// skipped.
CsvData parse_csv(const std::string& text, const std::string& name);
// Reads and parses a CSV file. Throws InputError(path, "", "a readable file") if missing.
CsvData read_csv(const std::string& path);

// Every line end as '\n': CRLF (Windows) and a lone CR (spreadsheets' "CSV (Macintosh)")
// alike, so that lines are counted and comment lines found in either (parse_csv and
// strip_comment_lines do it themselves).
std::string with_newline_ends(const std::string& text);

// Blank out '#' comment lines (keeping the line count, so later errors name the right
// line) for the CSV reader, which knows no comments. A leading byte-order mark is dropped.
std::string strip_comment_lines(const std::string& text);

}  // namespace millwear::io

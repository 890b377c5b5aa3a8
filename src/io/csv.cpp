#include "io/csv.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "io/atomic_write.hpp"

namespace millwear::io {

std::string format_number(double v, int digits) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (digits < 1) digits = 1;
  if (digits > 17) digits = 17;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string format_exact(double v) { return format_number(v, 17); }

std::string format_shortest(double v) {
  // %g writes an exponent once the value's own exponent reaches the digits asked for: 20 at
  // one digit is "2e+01". Where %g writes a number plainly at 17 digits (1e-4 to 1e16), the
  // text is the plain one: a whole number as one ("20", "1500"), a fraction as typed ("0.7").
  const bool plain = std::fabs(v) >= 1e-4 && std::fabs(v) < 1e16;
  for (int digits = 1; digits < 17; ++digits) {
    const std::string text = format_number(v, digits);
    if (plain && text.find('e') != std::string::npos) continue;
    if (std::strtod(text.c_str(), nullptr) == v) return text;
  }
  return format_exact(v);
}

std::string format_for_table(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string quote_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  q += '"';
  return q;
}

CsvTable::CsvTable(std::vector<std::string> header, CsvOptions options)
    : header_(std::move(header)), options_(options) {}

CsvTable& CsvTable::add_row(std::vector<CsvCell> row) {
  if (row.size() != header_.size())
    throw std::invalid_argument("CSV row has " + std::to_string(row.size()) +
                                " fields, header has " + std::to_string(header_.size()));
  std::vector<std::string> out;
  out.reserve(row.size());
  for (const auto& cell : row) {
    if (const auto* s = std::get_if<std::string>(&cell.value)) {
      out.push_back(quote_field(*s));
    } else if (const auto* d = std::get_if<double>(&cell.value)) {
      out.push_back(options_.exact ? format_exact(*d)
                                   : format_number(*d, options_.significant_digits));
    } else {
      out.push_back(std::to_string(std::get<long long>(cell.value)));
    }
  }
  rows_.push_back(std::move(out));
  return *this;
}

std::string CsvTable::str() const {
  std::string s;
  for (std::size_t i = 0; i < header_.size(); ++i) {
    if (i) s += ',';
    s += quote_field(header_[i]);
  }
  s += '\n';
  for (const auto& row : rows_) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) s += ',';
      s += row[i];
    }
    s += '\n';
  }
  return s;
}

void CsvTable::write(const std::string& path) const { write_file_atomic(path, str()); }

// ---- reading ----

bool CsvData::has_column(const std::string& name) const {
  for (const auto& h : header)
    if (h == name) return true;
  return false;
}

std::size_t CsvData::column(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  throw InputError(path, "line " + std::to_string(header_line), "a column named " + name);
}

const std::string& CsvData::text(std::size_t row, std::size_t col) const {
  return rows.at(row).at(col);
}

namespace {

// Digits in groups of three after points, as a thousands separator writes them: "1.000",
// "-12.500.000" (blanks around allowed).
bool thousands_grouped(const std::string& field) {
  const std::string t = trim(field);
  std::size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
  const std::size_t digits_from = i;
  while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i;
  if (i == digits_from || i - digits_from > 3 || i == t.size()) return false;
  while (i < t.size()) {
    if (t[i] != '.' || t.size() - i < 4) return false;
    for (std::size_t k = 1; k <= 3; ++k)
      if (!std::isdigit(static_cast<unsigned char>(t[i + k]))) return false;
    i += 4;
  }
  return true;
}

// A field that is a number with one comma as its decimal point: "385,5", "-0,25", ",5".
bool decimal_comma_number(const std::string& field) {
  const std::string t = trim(field);
  std::size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
  std::size_t digits = 0, commas = 0;
  for (; i < t.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(t[i]))) ++digits;
    else if (t[i] == ',') ++commas;
    else return false;
  }
  return commas == 1 && digits > 0 && t.back() != ',';
}

}  // namespace

double CsvData::number(std::size_t row, std::size_t col) const {
  const std::string& field = text(row, col);
  // A file that writes decimal commas writes its thousands with points: "1.000" is a thousand
  // there, which strtod would read as one. Refused, not guessed at.
  if (separator == ';' && decimal_comma_line != 0 && thousands_grouped(field))
    throw InputError(path, "line " + std::to_string(row_line.at(row)),
                     "a number in column " + header.at(col) + " without a thousands separator (this ';'-separated file "
                     "writes decimals with a comma, as '" + shown_text(decimal_comma_example) + "' on line " +
                     std::to_string(decimal_comma_line) + ", so its '.' groups thousands), found '" +
                     shown_text(field) + "'");
  // In a ';' file (European spreadsheets) the decimal separator is a comma: one comma and
  // no point reads as the point. A point and a comma together (a thousands separator) is
  // refused, not guessed at.
  std::string s = field;
  if (separator == ';') {
    const auto comma = s.find(',');
    if (comma != std::string::npos) {
      if (s.find(',', comma + 1) != std::string::npos || s.find('.') != std::string::npos)
        throw InputError(path, "line " + std::to_string(row_line.at(row)),
                         "a number in column " + header.at(col) +
                             " (';'-separated: a decimal comma and no thousands separator), found '" + shown_text(field) + "'");
      s[comma] = '.';
    }
  }
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(begin, &end);
  // strtod reads "0x14" as 20: no spreadsheet or gauge writes hexadecimal, so it is a typo.
  const char* digits = begin + std::strspn(begin, " \t+-");
  bool ok = end != begin && !(digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X'));
  if (ok) {
    // To the field's end, not the first NUL byte: "2\0" "0" is no number.
    const char* stop = begin + s.size();
    while (end < stop && (*end == ' ' || *end == '\t')) ++end;
    ok = end == stop;
  }
  // ERANGE on underflow gives a denormal or zero, which is fine; on overflow, it is not.
  if (ok && errno == ERANGE && std::isinf(v)) ok = false;
  if (!ok)
    throw InputError(path, "line " + std::to_string(row_line.at(row)),
                     "a number in column " + header.at(col) + ", found '" + shown_text(field) + "'");
  return v;
}

double CsvData::finite_number(std::size_t row, std::size_t col) const {
  const double v = number(row, col);
  if (!std::isfinite(v))
    throw InputError(path, "line " + std::to_string(row_line.at(row)),
                     "a finite number in column " + header.at(col) + ", found '" + shown_text(text(row, col)) + "'");
  return v;
}

std::vector<double> CsvData::finite_numbers(const std::string& col) const {
  const std::size_t c = column(col);
  std::vector<double> v;
  v.reserve(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) v.push_back(finite_number(r, c));
  return v;
}

std::vector<double> CsvData::numbers(const std::string& col) const {
  std::size_t c = column(col);
  std::vector<double> v;
  v.reserve(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) v.push_back(number(r, c));
  return v;
}

std::vector<std::string> CsvData::texts(const std::string& col) const {
  std::size_t c = column(col);
  std::vector<std::string> v;
  v.reserve(rows.size());
  for (const auto& row : rows) v.push_back(row.at(c));
  return v;
}

namespace {

// Splits the text into records of fields, tracking the line each record starts on.
struct Record {
  std::vector<std::string> fields;
  std::size_t line = 0;
};

// The separator, from the header (the first line that is not blank): ';' if it has a ';'
// and no ',' outside quotes, else ','.
char detect_separator(const std::string& text) {
  bool commas = false, semicolons = false, quoted = false, content = false;
  for (char c : text) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    if (c == '\n') {
      if (content) break;
      continue;
    }
    if (c != ' ' && c != '\t' && c != '\r') content = true;
    commas = commas || c == ',';
    semicolons = semicolons || c == ';';
  }
  return semicolons && !commas ? ';' : ',';
}

std::vector<Record> split_records(const std::string& text, const std::string& name, char sep) {
  std::vector<Record> records;
  std::size_t i = 0, n = text.size(), line = 1;
  while (i < n) {
    // Skip blank lines (including a lone '\r').
    if (text[i] == '\n') { ++line; ++i; continue; }
    if (text[i] == '\r' && (i + 1 == n || text[i + 1] == '\n')) { ++i; continue; }
    Record rec;
    rec.line = line;
    std::string field;
    bool at_line_end = false;
    while (!at_line_end) {
      field.clear();
      if (i < n && text[i] == '"') {
        std::size_t start_line = line;
        ++i;
        for (;;) {
          if (i >= n)
            throw InputError(name, "line " + std::to_string(start_line),
                             "a closing '\"' for the quoted field");
          char c = text[i++];
          if (c == '"') {
            if (i < n && text[i] == '"') { field += '"'; ++i; continue; }
            break;
          }
          if (c == '\n') ++line;
          field += c;
        }
        // Anything between the closing quote and the separator is an error.
        if (i < n && text[i] != sep && text[i] != '\n' && text[i] != '\r')
          throw InputError(name, "line " + std::to_string(line),
                           std::string("a ") + (sep == ';' ? "';'" : "comma") + " or line end after a quoted field");
      } else {
        while (i < n && text[i] != sep && text[i] != '\n' && text[i] != '\r') field += text[i++];
      }
      rec.fields.push_back(field);
      if (i < n && text[i] == sep) { ++i; continue; }
      // Line end or end of text.
      if (i < n && text[i] == '\r') ++i;
      if (i < n && text[i] == '\n') { ++i; ++line; }
      at_line_end = true;
    }
    records.push_back(std::move(rec));
  }
  return records;
}

}  // namespace

std::string with_newline_ends(const std::string& text) {
  if (text.find('\r') == std::string::npos) return text;
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\r') out += text[i];
    else if (i + 1 == text.size() || text[i + 1] != '\n') out += '\n';
  }
  return out;
}

CsvData parse_csv(const std::string& text_in, const std::string& name) {
  CsvData data;
  data.path = name;
  // Spreadsheets save "CSV UTF-8" with a byte-order mark; it is not part of the header.
  const bool bom = text_in.compare(0, 3, kUtf8Bom) == 0;
  if (text_in.compare(0, 2, "\xFF\xFE") == 0 || text_in.compare(0, 2, "\xFE\xFF") == 0)
    throw InputError(name, "line 1", "UTF-8 or ASCII text, found UTF-16 (save it as \"CSV UTF-8\" or plain CSV)");
  const std::string text = with_newline_ends(bom ? text_in.substr(3) : text_in);
  data.separator = detect_separator(text);
  std::vector<Record> records = split_records(text, name, data.separator);
  if (records.empty()) throw InputError(name, "line 1", "a header row");
  data.header = std::move(records[0].fields);
  for (std::string& h : data.header) h = trim(h);  // "x_mm, y_mm" as a spreadsheet may write it
  data.header_line = records[0].line;
  // A name twice leaves which column is meant to chance. (Unnamed columns, as a spreadsheet
  // may add at the end, are read by nobody.)
  for (std::size_t i = 0; i < data.header.size(); ++i)
    for (std::size_t j = i + 1; j < data.header.size(); ++j)
      if (!data.header[i].empty() && data.header[i] == data.header[j])
        throw InputError(name, "line " + std::to_string(data.header_line),
                         "each column named once, found '" + shown_text(data.header[i]) + "' as columns " +
                             std::to_string(i + 1) + " and " + std::to_string(j + 1));
  for (std::size_t r = 1; r < records.size(); ++r) {
    if (records[r].fields.size() != data.header.size())
      throw InputError(name, "line " + std::to_string(records[r].line),
                       std::to_string(data.header.size()) + " fields as in the header, found " +
                           std::to_string(records[r].fields.size()));
    data.rows.push_back(std::move(records[r].fields));
    data.row_line.push_back(records[r].line);
    if (data.separator == ';' && data.decimal_comma_line == 0)
      for (const std::string& f : data.rows.back())
        if (decimal_comma_number(f)) {
          data.decimal_comma_line = data.row_line.back();
          data.decimal_comma_example = trim(f);
          break;
        }
  }
  return data;
}

CsvData read_csv(const std::string& path) { return parse_csv(read_file(path), path); }

std::string strip_comment_lines(const std::string& text_in) {
  const std::string text = with_newline_ends(text_in);
  std::string out;
  out.reserve(text.size());
  // A byte-order mark (spreadsheets' "CSV UTF-8") would hide a first line's '#'.
  std::size_t pos = text.compare(0, 3, kUtf8Bom) == 0 ? 3 : 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    const bool last = end == std::string::npos;
    if (last) end = text.size();
    const std::string line = text.substr(pos, end - pos);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] != '#') out += line;
    if (!last) out += '\n';
    pos = end + 1;
  }
  return out;
}


}  // namespace millwear::io

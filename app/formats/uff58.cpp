#include "app/formats/uff58.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include "analysis/common/summary.h"
#include "app/core/checked_write.h"

// Layout of dataset 58 (SDRC/Siemens "Universal Dataset Number 58", as pyuff and the modal
// packages write it):
//   "    -1" / "    58" (58b: "    58b" + byte ordering, floating-point format, ASCII line count
//   (11) and byte count of the data block, format I6,A1,I6,I6,I12,I12,I6,I6,I12,I12)
//   records 1-5   80A1 id lines
//   record 6      2(I5,I10),2(1X,10A1,I10,I4): function type, function id, version, load case,
//                 response entity, node, direction, reference entity, node, direction
//   record 7      3I10,3E13.5: ordinate type (2 real single, 4 real double, 5 complex single,
//                 6 complex double), number of points, abscissa spacing (1 even, 0 uneven),
//                 abscissa minimum, increment, z-axis value
//   records 8-11  I10,3I5,2(1X,20A1): specific data type, length/force/temperature unit
//                 exponents, axis label, axis unit (abscissa, ordinate, denominator, z axis)
//   record 12     the values: per point [x] re [im] (x only for an uneven abscissa), in text
//                 (E13.5 single, E20.12 double) or, for 58b, raw IEEE 754 values of the
//                 ordinate's precision (x too)
//   "    -1"
namespace chatterlab::app::uff {
namespace {

using Text = std::string_view;

Text without_eol(Text line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.remove_suffix(1);
  return line;
}

std::string trimmed(Text s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return std::string(s);
}

// "NONE" is the format's word for an empty text field.
std::string text_field(Text s) {
  std::string t = trimmed(s);
  return t == "NONE" ? std::string() : t;
}

std::string none_if_empty(const std::string& s) { return s.empty() ? "NONE" : s; }

Text field(Text line, std::size_t begin, std::size_t width) {
  if (begin >= line.size()) return {};
  return line.substr(begin, width);
}

// A number as Fortran writes it: blanks around, a leading '+', a 'D' exponent.
bool parse_number(Text s, double& v) {
  std::string t = trimmed(s);
  if (!t.empty() && t.front() == '+') t.erase(0, 1);
  for (auto& ch : t) {
    if (ch == 'D' || ch == 'd') ch = 'E';
  }
  if (t.empty()) return false;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && ptr == t.data() + t.size();
}

bool parse_int(Text s, long& v) {
  const std::string t = trimmed(s);
  if (t.empty()) {
    v = 0;  // a blank integer field reads as 0 (Fortran list-directed I format)
    return true;
  }
  const char* b = t.data() + (t.front() == '+' ? 1 : 0);
  const auto [ptr, ec] = std::from_chars(b, t.data() + t.size(), v);
  return ec == std::errc() && ptr == t.data() + t.size();
}

class Block {
 public:
  Block(const std::filesystem::path& file, int ordinal) : file_(file), ordinal_(ordinal) {}
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(file_.string() + ": dataset 58 #" + std::to_string(ordinal_) +
                     (where.empty() ? "" : ", " + where) + ": " + what);
  }
  long integer(Text line, std::size_t begin, std::size_t width, const std::string& where,
               const char* name) const {
    long v = 0;
    if (!parse_int(field(line, begin, width), v)) {
      fail(where, std::string(name) + " '" + trimmed(field(line, begin, width)) +
                      "' is not a whole number");
    }
    return v;
  }

 private:
  const std::filesystem::path& file_;
  int ordinal_;
};

// Reads the line starting at `pos`; advances `pos` past its '\n'. False at the end of text.
bool next_line(Text text, std::size_t& pos, Text& line) {
  if (pos >= text.size()) return false;
  std::size_t eol = text.find('\n', pos);
  if (eol == Text::npos) eol = text.size();
  line = without_eol(text.substr(pos, eol - pos));
  pos = eol + 1;
  return true;
}

bool is_delimiter_line(Text line) { return trimmed(line) == "-1"; }

int values_per_point(const Function58& f, bool even) {
  return (even ? 0 : 1) + (f.complex_ordinate ? 2 : 1);
}

void read_axis(const Block& b, Text line, int record, std::string& label, std::string& unit) {
  const std::string where = "record " + std::to_string(record);
  if (line.size() < 25) b.fail(where, "line too short for I10,3I5,2(1X,20A1)");
  b.integer(line, 0, 10, where, "specific data type");
  label = text_field(field(line, 25, 21));
  unit = text_field(field(line, 46, Text::npos));
}

// The values of record 12 as text: every number of the lines up to the "-1" line, read in
// order (fields may touch, "-1.2E-03-4.5E-03", as fixed-width E formats allow).
std::vector<double> text_values(const Block& b, Text text, std::size_t& pos, std::size_t expected) {
  std::vector<double> v;
  // Every value takes at least one character: a count record 7 states beyond the file is not
  // allocated (a 4 kB file claiming 10^9 points would reserve 8 GB).
  v.reserve(std::min(expected, text.size() - std::min(pos, text.size())));
  Text line;
  int line_no = 12;
  while (true) {
    if (!next_line(text, pos, line)) {
      b.fail("record 12", "no \"-1\" line ends the dataset (truncated file?)");
    }
    if (is_delimiter_line(line)) break;
    ++line_no;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i >= line.size()) break;
      // One number: sign, mantissa, exponent; a sign after a digit starts the next number
      // unless it follows the exponent letter.
      std::size_t j = i + 1;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') {
        const char c = line[j];
        if ((c == '-' || c == '+') && !(line[j - 1] == 'E' || line[j - 1] == 'e' ||
                                        line[j - 1] == 'D' || line[j - 1] == 'd')) {
          break;
        }
        ++j;
      }
      double x = 0;
      if (!parse_number(line.substr(i, j - i), x)) {
        b.fail("record 12", "'" + std::string(line.substr(i, j - i)) + "' on data line " +
                                std::to_string(line_no - 12) + " is not a number");
      }
      v.push_back(x);
      i = j;
    }
  }
  return v;
}

template <typename T>
T load(const char* p, bool swap) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

bool host_little_endian() {
  const std::uint16_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

Function58 read_block(const Block& b, Text text, std::size_t& pos, Text header) {
  // Header line: "    58" or "    58b" with the binary layout's fields.
  const bool binary = header.size() > 6 && (header[6] == 'b' || header[6] == 'B');
  long byte_order = 1, fp_format = 2, ascii_lines = 11, n_bytes = 0;
  if (binary) {
    std::istringstream in{std::string(header.substr(7))};
    if (!(in >> byte_order >> fp_format >> ascii_lines >> n_bytes)) {
      b.fail("58b header", "byte ordering, floating-point format, line and byte counts expected");
    }
    if (byte_order != 1 && byte_order != 2) {
      b.fail("58b header", "byte ordering " + std::to_string(byte_order) +
                               ": must be 1 (little endian) or 2 (big endian)");
    }
    if (fp_format != 2) {
      b.fail("58b header", "floating-point format " + std::to_string(fp_format) +
                               ": only 2 (IEEE 754) is read (1 is DEC VMS, 3 IBM 370)");
    }
    if (ascii_lines != 11) {
      b.fail("58b header", std::to_string(ascii_lines) + " ASCII header lines: must be 11");
    }
  }
  Text lines[11];
  for (int r = 0; r < 11; ++r) {
    if (!next_line(text, pos, lines[r]) || is_delimiter_line(lines[r])) {
      b.fail("record " + std::to_string(r + 1), "missing (the dataset ends early)");
    }
  }
  Function58 f;
  f.id1 = text_field(lines[0]);
  f.id2 = text_field(lines[1]);
  f.id3 = text_field(lines[2]);
  f.id4 = text_field(lines[3]);
  f.id5 = text_field(lines[4]);

  const Text r6 = lines[5];
  f.function_type = static_cast<int>(b.integer(r6, 0, 5, "record 6", "function type"));
  f.load_case = static_cast<int>(b.integer(r6, 20, 10, "record 6", "load case"));
  f.response_entity = text_field(field(r6, 30, 11));
  f.response_node = static_cast<int>(b.integer(r6, 41, 10, "record 6", "response node"));
  f.response_direction = static_cast<int>(b.integer(r6, 51, 4, "record 6", "response direction"));
  f.reference_entity = text_field(field(r6, 55, 11));
  f.reference_node = static_cast<int>(b.integer(r6, 66, 10, "record 6", "reference node"));
  f.reference_direction = static_cast<int>(b.integer(r6, 76, 4, "record 6", "reference direction"));

  // Record 7: blank-separated when its six fields are (wider E fields than E13.5 included),
  // else the fixed columns 3I10,3E13.5.
  const Text r7 = lines[6];
  long ord_type = 0, n = 0, spacing = 0;
  double x_min = 0, dx = 0, z = 0;
  {
    std::istringstream in{std::string(r7)};
    std::vector<std::string> tok;
    for (std::string s; in >> s;) tok.push_back(s);
    bool ok = tok.size() == 6 && parse_int(tok[0], ord_type) && parse_int(tok[1], n) &&
              parse_int(tok[2], spacing) && parse_number(tok[3], x_min) &&
              parse_number(tok[4], dx) && parse_number(tok[5], z);
    if (!ok) {
      ord_type = b.integer(r7, 0, 10, "record 7", "ordinate data type");
      n = b.integer(r7, 10, 10, "record 7", "number of points");
      spacing = b.integer(r7, 20, 10, "record 7", "abscissa spacing");
      const char* names[] = {"abscissa minimum", "abscissa increment", "z-axis value"};
      double* out[] = {&x_min, &dx, &z};
      for (int i = 0; i < 3; ++i) {
        const Text s = field(r7, 30 + 13 * static_cast<std::size_t>(i), 13);
        if (!parse_number(s, *out[i])) {
          b.fail("record 7", std::string(names[i]) + " '" + trimmed(s) + "' is not a number");
        }
      }
    }
  }
  if (ord_type != 2 && ord_type != 4 && ord_type != 5 && ord_type != 6) {
    b.fail("record 7", "ordinate data type " + std::to_string(ord_type) +
                           ": must be 2 or 4 (real single or double), 5 or 6 (complex)");
  }
  if (spacing != 0 && spacing != 1) {
    b.fail("record 7",
           "abscissa spacing " + std::to_string(spacing) + ": must be 1 (even) or 0 (uneven)");
  }
  if (n <= 0) b.fail("record 7", "number of points " + std::to_string(n) + ": must be > 0");
  // Every point takes at least one byte of the file: a larger count cannot be read, and its
  // product with the values per point and their size could overflow.
  if (static_cast<unsigned long>(n) > text.size()) {
    b.fail("record 7", "number of points " + std::to_string(n) + ": more than the file's " +
                           std::to_string(text.size()) + " bytes can hold");
  }
  const bool even = spacing == 1;
  if (even && !(dx > 0)) {
    b.fail("record 7", "abscissa increment " + trimmed(field(r7, 43, 13)) +
                           ": must be > 0 for an even abscissa");
  }
  f.complex_ordinate = ord_type == 5 || ord_type == 6;
  f.x_start = x_min;
  f.dx = even ? dx : 0.0;
  read_axis(b, lines[7], 8, f.x_label, f.x_unit);
  read_axis(b, lines[8], 9, f.y_label, f.y_unit);
  read_axis(b, lines[9], 10, f.z_label, f.z_unit);
  std::string z_label, z_unit;
  read_axis(b, lines[10], 11, z_label, z_unit);

  const std::size_t per = static_cast<std::size_t>(values_per_point(f, even));
  const std::size_t expected = static_cast<std::size_t>(n) * per;
  std::vector<double> v;
  if (binary) {
    const std::size_t size = ord_type == 2 || ord_type == 5 ? 4 : 8;
    if (static_cast<std::size_t>(n_bytes) != expected * size) {
      b.fail("58b header", std::to_string(n_bytes) + " data bytes, record 7 implies " +
                               std::to_string(expected * size) + " (" + std::to_string(n) +
                               " points x " + std::to_string(per) + " values x " +
                               std::to_string(size) + " bytes)");
    }
    if (pos + expected * size > text.size()) {
      b.fail("record 12", "the file ends inside the binary data block (" +
                              std::to_string(text.size() - std::min(pos, text.size())) + " of " +
                              std::to_string(expected * size) + " bytes)");
    }
    const bool swap = (byte_order == 1) != host_little_endian();
    v.resize(expected);
    const char* p = text.data() + pos;
    for (std::size_t i = 0; i < expected; ++i) {
      v[i] = size == 4 ? static_cast<double>(load<float>(p + 4 * i, swap))
                       : load<double>(p + 8 * i, swap);
    }
    pos += expected * size;
    // The "-1" may follow the data directly (pyuff) or after a line end.
    while (pos < text.size() && std::strchr(" \t\r\n", text[pos]) != nullptr) ++pos;
    if (text.substr(pos, 2) != "-1") {
      b.fail("record 12", "no \"-1\" line after the binary data block");
    }
    Text rest;
    next_line(text, pos, rest);
  } else {
    v = text_values(b, text, pos, expected);
    if (v.size() != expected) {
      b.fail("record 12", std::to_string(v.size()) + " values, record 7 implies " +
                              std::to_string(expected) + " (" + std::to_string(n) + " points x " +
                              std::to_string(per) + " values)");
    }
  }
  const Eigen::Index np = static_cast<Eigen::Index>(n);
  if (!even) f.x.resize(np);
  if (f.complex_ordinate) {
    f.values.resize(np);
  } else {
    f.real.resize(np);
  }
  for (Eigen::Index i = 0; i < np; ++i) {
    const std::size_t k = static_cast<std::size_t>(i) * per;
    std::size_t c = k;
    if (!even) f.x[i] = v[c++];
    if (f.complex_ordinate) {
      f.values[i] = {v[c], v[c + 1]};
    } else {
      f.real[i] = v[c];
    }
  }
  return f;
}

// ---- Writing ----------------------------------------------------------------------------------

std::string fixed(const std::string& s, std::size_t width) {
  return s.size() > width ? s.substr(0, width) : s;
}

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  const int n = std::vsnprintf(buf, sizeof(buf), fmt, args);
  va_end(args);
  return std::string(buf, static_cast<std::size_t>(std::max(n, 0)));
}

// Record 8 field 1 for an axis: 17 time, 18 frequency (from its unit), else 0 (unknown).
int specific_type(const std::string& unit) {
  if (unit == "s") return 17;
  if (unit == "Hz") return 18;
  return 0;
}

std::string axis_line(const std::string& label, const std::string& unit) {
  return format("%10d%5d%5d%5d %-20s %-20s\n", specific_type(unit), 0, 0, 0,
                fixed(none_if_empty(label), 20).c_str(), fixed(none_if_empty(unit), 20).c_str());
}

void check_writable(const std::filesystem::path& file, const Function58& f, std::size_t i) {
  const std::string where =
      file.string() + ": function " + std::to_string(i + 1) + " ('" + f.id1 + "'): ";
  const Eigen::Index n = f.samples();
  if (f.complex_ordinate ? f.real.size() != 0 : f.values.size() != 0) {
    throw InputError(where + "complex_ordinate is " + (f.complex_ordinate ? "true" : "false") +
                     " but the other ordinate vector holds values");
  }
  if (n == 0) throw InputError(where + "no values");
  if (f.x.size() != 0 && f.x.size() != n) {
    throw InputError(where + "x has " + std::to_string(f.x.size()) + " values, the ordinate " +
                     std::to_string(n));
  }
  if (f.x.size() == 0 && !(f.dx > 0)) {
    throw InputError(where + "dx = " + std::to_string(f.dx) + ": must be > 0 (even abscissa)");
  }
}

}  // namespace

std::vector<Function58> read_uff58(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open");
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const Text text(content);
  std::vector<Function58> out;
  std::size_t pos = 0;
  Text line;
  int ordinal = 0;
  while (next_line(text, pos, line)) {
    if (!is_delimiter_line(line)) continue;  // blank lines between datasets
    Text header;
    if (!next_line(text, pos, header)) break;
    const std::string number = trimmed(field(header, 0, 6));
    const bool binary = header.size() > 6 && (header[6] == 'b' || header[6] == 'B');
    if (number == "58") {
      ++ordinal;
      out.push_back(read_block(Block(file, ordinal), text, pos, header));
      continue;
    }
    // Another dataset: skip to its "-1". A binary one states its byte count after the line
    // count (58b layout, shared by the binary forms of other datasets).
    if (binary) {
      std::istringstream h{std::string(header.substr(7))};
      long bo = 0, fp = 0, lines = 0, bytes = 0;
      if (h >> bo >> fp >> lines >> bytes && lines >= 0 && bytes >= 0) {
        for (long i = 0; i < lines && next_line(text, pos, line); ++i) {
        }
        pos += static_cast<std::size_t>(bytes);
      }
    }
    while (next_line(text, pos, line) && !is_delimiter_line(line)) {
    }
  }
  return out;
}

void write_uff58(const std::filesystem::path& file, const std::vector<Function58>& functions,
                 bool binary) {
  for (std::size_t i = 0; i < functions.size(); ++i) check_writable(file, functions[i], i);
  std::ofstream out = open_for_writing(file);
  for (const auto& f : functions) {
    const bool even = f.x.size() == 0;
    const Eigen::Index n = f.samples();
    const int per = values_per_point(f, even);
    const int ord_type = f.complex_ordinate ? 6 : 4;  // always double precision
    std::vector<double> v;
    v.reserve(static_cast<std::size_t>(n * per));
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!even) v.push_back(f.x[i]);
      if (f.complex_ordinate) {
        v.push_back(f.values[i].real());
        v.push_back(f.values[i].imag());
      } else {
        v.push_back(f.real[i]);
      }
    }
    std::string h = format("%6d\n%6d", -1, 58);
    if (binary) {
      h += format("b%6d%6d%12d%12zu%6d%6d%12d%12d\n", host_little_endian() ? 1 : 2, 2, 11,
                  v.size() * 8, 0, 0, 0, 0);
    } else {
      h += "\n";
    }
    for (const auto* id : {&f.id1, &f.id2, &f.id3, &f.id4, &f.id5}) {
      h += format("%-80s\n", fixed(none_if_empty(*id), 80).c_str());
    }
    h += format("%5d%10d%5d%10d %10s%10d%4d %10s%10d%4d\n", f.function_type, 0, 0, f.load_case,
                fixed(none_if_empty(f.response_entity), 10).c_str(), f.response_node,
                f.response_direction, fixed(none_if_empty(f.reference_entity), 10).c_str(),
                f.reference_node, f.reference_direction);
    h += format("%10d%10lld%10d%13.5E%13.5E%13.5E\n", ord_type, static_cast<long long>(n),
                even ? 1 : 0, even ? f.x_start : 0.0, even ? f.dx : 0.0, 0.0);
    h += axis_line(f.x_label, f.x_unit);
    h += axis_line(f.y_label, f.y_unit);
    h += axis_line(f.z_label, f.z_unit);
    h += axis_line("", "");
    out << h;
    if (binary) {
      // The host's byte order, stated in the header (1 little endian, 2 big endian).
      out.write(reinterpret_cast<const char*>(v.data()),
                static_cast<std::streamsize>(v.size() * sizeof(double)));
    } else {
      // Double precision: 4E20.12 even; 2(E13.5,E20.12) real uneven; E13.5,2E20.12 complex
      // uneven (the abscissa of an uneven function in single precision, as the format has it).
      std::string body;
      const std::size_t per_line = even ? 4 : (f.complex_ordinate ? 3 : 4);
      for (std::size_t k = 0; k < v.size(); ++k) {
        const bool x_value = !even && k % static_cast<std::size_t>(per) == 0;
        body += format(x_value ? "%13.5E" : "%20.12E", v[k]);
        if ((k + 1) % per_line == 0 || k + 1 == v.size()) body += '\n';
      }
      out << body;
    }
    out << format("%6d\n", -1);
  }
  close_checked(out, file);
}

}  // namespace chatterlab::app::uff

#include "app/formats/frf_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "app/core/checked_write.h"

namespace chatterlab::app::frf_text {

namespace {

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  std::string t = s.substr(a, b - a);
  if (t.size() >= 2 && (t.front() == '"' || t.front() == '\'') && t.back() == t.front()) {
    t = t.substr(1, t.size() - 2);
  }
  return t;
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool starts_with(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

std::vector<std::string> split(const std::string& line, char delimiter) {
  std::vector<std::string> out;
  if (delimiter == ' ') {
    std::istringstream in(line);
    std::string f;
    while (in >> f) out.push_back(trim(f));
    return out;
  }
  std::string cur;
  for (char c : line) {
    if (c == delimiter) {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  // A trailing delimiter (some exports end every row with one) adds no column.
  if (out.size() > 1 && out.back().empty()) out.pop_back();
  return out;
}

std::optional<double> number(std::string s, char decimal) {
  if (s.empty()) return std::nullopt;
  if (decimal == ',') {
    if (s.find('.') != std::string::npos) return std::nullopt;
    std::replace(s.begin(), s.end(), ',', '.');
  }
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

bool all_numbers(const std::vector<std::string>& fields, char decimal) {
  return std::all_of(fields.begin(), fields.end(),
                     [&](const std::string& f) { return number(f, decimal).has_value(); });
}

bool is_comment(const std::string& t) {
  return t.empty() || t[0] == '#' || t[0] == '%' || starts_with(t, "//");
}

// The dialect of a data row: the first candidate that splits it into >= 3 numbers.
std::optional<std::pair<char, char>> detect(const std::string& line, const ReadOptions& o) {
  static const std::pair<char, char> kCandidates[] = {
      {';', ','}, {';', '.'}, {'\t', '.'}, {'\t', ','}, {',', '.'}, {' ', '.'}, {' ', ','}};
  for (const auto& [d, m] : kCandidates) {
    if (o.delimiter && o.delimiter != d) continue;
    if (o.decimal && o.decimal != m) continue;
    if (d == ',' && m == ',') continue;
    if (d != ' ' && line.find(d) == std::string::npos) continue;
    const auto f = split(line, d);
    if (f.size() >= 3 && all_numbers(f, m)) return std::make_pair(d, m);
  }
  return std::nullopt;
}

std::string dialect_name(char d, char m) {
  const std::string ds = d == ' ' ? "whitespace" : d == '\t' ? "tab" : std::string("'") + d + "'";
  return ds + " delimiter, decimal '" + std::string(1, m) + "'";
}

enum class Role { kNone, kFrequency, kReal, kImag, kMagnitude, kPhase, kCoherence };

struct Header {
  std::string base;  // lowercased name without the unit
  std::string unit;  // lowercased text in () or [], or after the last '_' for _hz/_deg/_rad
};

Header parse_header(const std::string& field) {
  Header h;
  std::string s = lower(trim(field));
  const auto open = s.find_first_of("([");
  if (open != std::string::npos) {
    const auto close = s.find_first_of(")]", open);
    h.unit =
        trim(s.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1));
    s = trim(s.substr(0, open));
  }
  for (const char* suffix : {"_hz", "_khz", "_deg", "_rad", "_db"}) {
    const std::string sf(suffix);
    if (s.size() > sf.size() && s.compare(s.size() - sf.size(), sf.size(), sf) == 0) {
      if (h.unit.empty()) h.unit = sf.substr(1);
      if (sf != "_hz" || s != "f_hz") s = s.substr(0, s.size() - sf.size());
    }
  }
  h.base = s;
  return h;
}

Role role_of(const Header& h) {
  const std::string& b = h.base;
  if (b == "f" || b == "f_hz" || b == "hz" || starts_with(b, "freq")) return Role::kFrequency;
  if (b == "re" || starts_with(b, "real") || starts_with(b, "re(") || b == "h_re")
    return Role::kReal;
  if (b == "im" || starts_with(b, "imag") || starts_with(b, "im(") || b == "h_im")
    return Role::kImag;
  if (starts_with(b, "mag") || starts_with(b, "abs") || starts_with(b, "amp") || b == "|h|")
    return Role::kMagnitude;
  if (starts_with(b, "phase") || b == "ph" || b == "angle" || b == "arg") return Role::kPhase;
  if (starts_with(b, "coh")) return Role::kCoherence;
  return Role::kNone;
}

struct Layout {
  int f = -1, re = -1, im = -1, mag = -1, ph = -1, coh = -1;
  double f_scale = 1.0;
  bool phase_rad = false, mag_db = false;
  bool polar() const { return re < 0 || im < 0; }
};

// Columns named by a header row; nullopt when it names no frequency and no complex pair.
std::optional<Layout> layout_from_header(const std::vector<std::string>& names,
                                         std::string& described) {
  Layout l;
  std::vector<std::string> used;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const Header h = parse_header(names[i]);
    const int c = static_cast<int>(i);
    int* slot = nullptr;
    switch (role_of(h)) {
      case Role::kFrequency:
        slot = &l.f;
        break;
      case Role::kReal:
        slot = &l.re;
        break;
      case Role::kImag:
        slot = &l.im;
        break;
      case Role::kMagnitude:
        slot = &l.mag;
        break;
      case Role::kPhase:
        slot = &l.ph;
        break;
      case Role::kCoherence:
        slot = &l.coh;
        break;
      case Role::kNone:
        break;
    }
    if (slot == nullptr || *slot >= 0) continue;
    *slot = c;
    if (slot == &l.f) {
      if (h.unit == "khz") l.f_scale = 1e3;
      if (h.unit == "rad/s") l.f_scale = 1.0 / kTwoPi;
    }
    if (slot == &l.ph) l.phase_rad = h.unit.find("rad") != std::string::npos;
    if (slot == &l.mag) l.mag_db = h.unit.find("db") != std::string::npos;
  }
  if (l.f < 0 || ((l.re < 0 || l.im < 0) && (l.mag < 0 || l.ph < 0))) return std::nullopt;
  auto name = [&](int c) { return "'" + trim(names[static_cast<std::size_t>(c)]) + "'"; };
  described = name(l.f) + ", ";
  described += l.polar() ? name(l.mag) + ", " + name(l.ph) : name(l.re) + ", " + name(l.im);
  if (l.coh >= 0) described += ", " + name(l.coh);
  return l;
}

}  // namespace

FrfTable read_frf_text(const std::filesystem::path& file, const std::string& label,
                       const ReadOptions& options) {
  std::ifstream in(file);
  if (!in) throw InputError(label + ": file not found or not readable");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  // The first data row fixes the dialect; the last non-comment line before it may be a header.
  std::size_t first = lines.size();
  std::pair<char, char> dialect{0, 0};
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string t = trim(lines[i]);
    if (is_comment(t)) continue;
    if (const auto d = detect(t, options)) {
      first = i;
      dialect = *d;
      break;
    }
  }
  if (first == lines.size()) {
    std::string stated;
    if (options.delimiter || options.decimal) {
      stated = " in the stated dialect (" +
               dialect_name(options.delimiter ? options.delimiter : ',',
                            options.decimal ? options.decimal : '.') +
               ")";
    }
    throw InputError(label +
                     ": no data row of at least three numbers (frequency, real, "
                     "imaginary)" +
                     stated);
  }
  // Plain variables, not a structured binding: lambdas below capture them (C++17, clang).
  const char delim = dialect.first;
  const char decimal = dialect.second;
  const std::size_t width = split(trim(lines[first]), delim).size();

  FrfTable out;
  out.delimiter = delim;
  out.decimal = decimal;
  Layout layout;
  layout.f = 0;
  layout.re = 1;
  layout.im = 2;
  out.columns = "frequency, real, imaginary: the first three columns (no header names them)";
  for (std::size_t i = first; i-- > 0;) {
    const std::string t = trim(lines[i]);
    if (is_comment(t)) continue;
    const auto names = split(t, delim);
    std::string described;
    if (names.size() == width) {
      if (const auto l = layout_from_header(names, described)) {
        layout = *l;
        out.columns = described + " by the header on line " + std::to_string(i + 1);
      }
    }
    break;  // only the line right before the data can be the header
  }
  if (width > 3 && out.columns.find("first three") != std::string::npos) {
    out.warnings.push_back(label + ": " + std::to_string(width) +
                           " columns and no header naming them: the first three are taken as "
                           "frequency, real, imaginary");
  }

  std::vector<double> f, a, b, coh;
  std::vector<std::size_t> line_of;
  for (std::size_t i = first; i < lines.size(); ++i) {
    const std::string t = trim(lines[i]);
    if (is_comment(t)) continue;
    const std::string where = label + " line " + std::to_string(i + 1);
    const auto fields = split(t, delim);
    if (fields.size() != width) {
      throw InputError(where + ": " + std::to_string(fields.size()) +
                       " fields, the first data row (line " + std::to_string(first + 1) + ") has " +
                       std::to_string(width) + " (" + dialect_name(delim, decimal) + ")");
    }
    auto value = [&](int c, const char* what) {
      const auto v = number(fields[static_cast<std::size_t>(c)], decimal);
      if (!v) {
        throw InputError(where + ", column " + std::to_string(c + 1) + " (" + what + "): '" +
                         fields[static_cast<std::size_t>(c)] + "' is not a number (" +
                         dialect_name(delim, decimal) + ")");
      }
      if (!std::isfinite(*v)) {
        throw InputError(where + ", column " + std::to_string(c + 1) + " (" + what +
                         "): not a finite number");
      }
      return *v;
    };
    f.push_back(value(layout.f, "frequency") * layout.f_scale);
    if (layout.polar()) {
      a.push_back(value(layout.mag, "magnitude"));
      b.push_back(value(layout.ph, "phase"));
    } else {
      a.push_back(value(layout.re, "real"));
      b.push_back(value(layout.im, "imaginary"));
    }
    if (layout.coh >= 0) {
      const double c = value(layout.coh, "coherence");
      if (c < 0 || c > 1.0 + 1e-9) {
        throw InputError(where + ", column " + std::to_string(layout.coh + 1) + " (coherence): " +
                         fields[static_cast<std::size_t>(layout.coh)] + " is outside [0, 1]");
      }
      coh.push_back(c);
    }
    line_of.push_back(i + 1);
  }

  // A 0 Hz row (DC) carries no dynamics and cannot become a receptance: dropped.
  std::size_t start = 0;
  if (!f.empty() && f[0] == 0.0) {
    start = 1;
    out.warnings.push_back(label + " line " + std::to_string(line_of[0]) +
                           ": the 0 Hz row is not used");
  }
  const std::size_t n = f.size() - start;
  if (n < 3) {
    throw InputError(label + ": " + std::to_string(n) +
                     " frequency row(s) above 0 Hz; an FRF needs at least 3");
  }
  for (std::size_t i = start; i < f.size(); ++i) {
    if (f[i] < 0) {
      throw InputError(label + " line " + std::to_string(line_of[i]) + ": frequency " +
                       std::to_string(f[i]) + " Hz is negative");
    }
    if (i > start && !(f[i] > f[i - 1])) {
      throw InputError(label + " line " + std::to_string(line_of[i]) +
                       ": frequencies must increase (this row's is not above the previous row's)");
    }
  }
  const double df = (f.back() - f[start]) / static_cast<double>(n - 1);
  for (std::size_t i = start; i < f.size(); ++i) {
    const double expected = f[start] + static_cast<double>(i - start) * df;
    if (std::abs(f[i] - expected) > 0.25 * df) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    ": frequency %.6g Hz is off the even grid (%.6g Hz + k x %.6g Hz); FRF rows "
                    "must be evenly spaced",
                    f[i], f[start], df);
      throw InputError(label + " line " + std::to_string(line_of[i]) + buf);
    }
  }
  out.df_hz = df;
  out.f_hz.resize(static_cast<Eigen::Index>(n));
  out.h.resize(static_cast<Eigen::Index>(n));
  if (!coh.empty()) out.coherence.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const std::size_t s = i + start;
    out.f_hz[k] = f[s];
    if (layout.polar()) {
      const double mag = layout.mag_db ? std::pow(10.0, a[s] / 20.0) : a[s];
      const double ph = layout.phase_rad ? b[s] : b[s] * kDegToRad;
      out.h[k] = std::polar(mag, ph);
    } else {
      out.h[k] = {a[s], b[s]};
    }
    if (!coh.empty()) out.coherence[k] = coh[s];
  }
  return out;
}

Eigen::VectorXcd to_receptance(const Eigen::VectorXd& f_hz, const Eigen::VectorXcd& h,
                               Ordinate ordinate) {
  Eigen::VectorXcd r(h.size());
  for (Eigen::Index i = 0; i < h.size(); ++i) {
    const std::complex<double> jw(0.0, kTwoPi * f_hz[i]);
    switch (ordinate) {
      case Ordinate::kReceptance:
        r[i] = h[i];
        break;
      case Ordinate::kMobility:
        r[i] = h[i] / jw;
        break;
      case Ordinate::kAccelerance:
        r[i] = h[i] / (jw * jw);
        break;
    }
  }
  return r;
}

void write_csv(const std::filesystem::path& file, const std::vector<std::string>& comments,
               const std::vector<Column>& columns) {
  std::ofstream out = open_for_writing(file);
  for (const auto& c : comments) out << "# " << c << "\n";
  Eigen::Index rows = 0;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    out << (i ? "," : "") << columns[i].name;
    rows = std::max(rows, columns[i].values.size());
  }
  out << "\n";
  char buf[40];
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      if (i) out << ',';
      const auto& v = columns[i].values;
      if (r < v.size() && std::isfinite(v[r])) {
        std::snprintf(buf, sizeof buf, "%.17g", v[r]);
        out << buf;
      }
    }
    out << "\n";
  }
  close_checked(out, file);
}

}  // namespace chatterlab::app::frf_text

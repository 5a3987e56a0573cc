#include "app/core/signals.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <set>

#include "analysis/common/summary.h"
#include "app/core/checked_write.h"
#include "app/core/input_boundary.h"
#include "app/core/yaml_reader.h"
#include "app/formats/matfile.h"
#include "app/formats/uff58.h"

namespace chatterlab::app {

class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& p, const std::string& label) {
    fd_ = ::open(p.c_str(), O_RDONLY);
    if (fd_ < 0) throw InputError(label + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(fd_, &st) != 0) {
      ::close(fd_);
      throw InputError(label + ": cannot read file size");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      void* p_map = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd_, 0);
      if (p_map == MAP_FAILED) {
        ::close(fd_);
        throw InputError(label + ": cannot map file (" + std::strerror(errno) + ")");
      }
      data_ = static_cast<const char*>(p_map);
      ::madvise(p_map, size_, MADV_SEQUENTIAL);
    }
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<char*>(data_), size_);
    if (fd_ >= 0) ::close(fd_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  const char* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  int fd_ = -1;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

namespace {

template <typename T>
double load_le(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // little-endian host (x86-64, aarch64)
  return static_cast<double>(v);
}

std::string sample_where(std::size_t i, const std::string& channel) {
  return "channel '" + channel + "', sample " + std::to_string(i);
}

std::string lower(std::string s) {
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::string joined(const std::vector<std::string>& names, const std::string& quote = "") {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + quote + n + quote;
  return out;
}

// ---- Delimited text dialects ----------------------------------------------------------------

std::string_view without_cr(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

bool blank(std::string_view line) {
  return line.find_first_not_of(" \t\r") == std::string_view::npos;
}

// The cells of a delimited line. A cell may be quoted ("1.5", "Force, N" as spreadsheets
// export them): the quotes go and a delimiter inside them is text. A last cell that is empty or
// blank (a row ending in the delimiter, as LabVIEW writes its rows) is dropped.
void split_cells(std::string_view line, char delim, std::vector<std::string_view>& cells,
                 bool drop_empty_last = true) {
  constexpr auto npos = std::string_view::npos;
  cells.clear();
  std::size_t pos = 0;
  while (true) {
    std::size_t q = pos;
    while (q < line.size() && line[q] != delim && (line[q] == ' ' || line[q] == '\t')) ++q;
    std::size_t close = npos;
    if (q < line.size() && line[q] == '"') {
      close = q + 1;
      while ((close = line.find('"', close)) != npos && close + 1 < line.size() &&
             line[close + 1] == '"') {
        close += 2;  // "" is a quote inside a quoted cell
      }
    }
    const std::size_t d = line.find(delim, close == npos ? pos : close + 1);
    cells.push_back(close == npos ? line.substr(pos, d == npos ? npos : d - pos)
                                  : line.substr(q + 1, close - q - 1));
    if (d == npos) break;
    pos = d + 1;
  }
  if (drop_empty_last && cells.size() > 1 && blank(cells.back())) cells.pop_back();
}

std::size_t cells_in(std::string_view line, char delim) {
  std::vector<std::string_view> cells;
  split_cells(line, delim, cells);
  return cells.size();
}

bool comment_cell(std::string_view cell) {
  std::string_view s = cell;
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s.size() == 7 && (s[0] == 'C' || s[0] == 'c') && s.substr(1) == "omment";
}

// The columns a header row names: its cells, but a last "Comment" cell (LabVIEW's column that
// rows leave empty) does not count.
std::size_t header_columns(std::string_view line, char delim) {
  std::vector<std::string_view> cells;
  split_cells(line, delim, cells);
  return cells.size() - (cells.size() > 1 && comment_cell(cells.back()) ? 1 : 0);
}

// One cell as a number: blanks around it and a leading '+' allowed; with a decimal comma the
// cell must not also hold a point (a thousands separator is not read).
template <bool kDecimalComma>
inline bool to_double(std::string_view s, double& v) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  if constexpr (kDecimalComma) {
    char buf[64];
    if (s.size() >= sizeof(buf)) return false;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] == '.') return false;
      buf[i] = s[i] == ',' ? '.' : s[i];
    }
    auto [ptr, err] = std::from_chars(buf, buf + s.size(), v);
    return err == std::errc() && ptr == buf + s.size();
  } else {
    auto [ptr, err] = std::from_chars(s.data(), s.data() + s.size(), v);
    return err == std::errc() && ptr == s.data() + s.size();
  }
}

bool number_in(std::string_view s, char decimal) {
  double v = 0;
  return decimal == ',' ? to_double<true>(s, v) : to_double<false>(s, v);
}

// Cells of `line` split at `delim`, each a number in `decimal`.
bool numeric_row(std::string_view line, char delim, char decimal, std::size_t* cells) {
  std::vector<std::string_view> c;
  split_cells(line, delim, c);
  for (const auto& cell : c) {
    if (!number_in(cell, decimal)) return false;
  }
  *cells = c.size();
  return true;
}

// A header row: some cell has a letter, and no cell reads as a number (either decimal mark).
bool names_row(std::string_view line, char delim) {
  bool letter = false;
  std::vector<std::string_view> c;
  split_cells(line, delim, c);
  for (const auto& cell : c) {
    if (number_in(cell, '.') || number_in(cell, ',')) return false;
    for (const char ch : cell) letter = letter || std::isalpha(static_cast<unsigned char>(ch));
  }
  return letter;
}

struct Dialect {
  char delimiter = ',';
  char decimal = '.';
  int skip_lines = 0;
  std::size_t columns = 0;
};

std::string delimiter_word(char d) { return d == '\t' ? "tab" : std::string("'") + d + "'"; }

std::string delimiter_yaml(char d) { return d == '\t' ? "tab" : std::string("\"") + d + "\""; }

// The first lines of `text` (at most 200 and 64 KiB), a partial last line dropped.
std::vector<std::string_view> head_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t pos = 0;
  const std::size_t limit = std::min<std::size_t>(text.size(), 64 * 1024);
  while (pos < text.size() && lines.size() < 200) {
    const std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) {
      if (text.size() <= limit) lines.push_back(without_cr(text.substr(pos)));
      break;
    }
    if (eol > limit) break;
    lines.push_back(without_cr(text.substr(pos, eol - pos)));
    pos = eol + 1;
  }
  return lines;
}

// The dialect a text file looks written in: for each delimiter and decimal mark, the first run
// of (up to 8) numeric rows with one cell count of two or more, right after a header row of
// that many cells, none a number and one with a letter. The most columns wins; ties go to the
// earlier candidate below.
std::optional<Dialect> sniff(const std::vector<std::string_view>& lines) {
  static constexpr std::array<std::array<char, 2>, 5> kCandidates = {
      {{',', '.'}, {';', '.'}, {'\t', '.'}, {';', ','}, {'\t', ','}}};
  std::optional<Dialect> best;
  for (const auto& [delim, decimal] : kCandidates) {
    for (std::size_t k = 1; k < lines.size(); ++k) {
      std::size_t n = 0;
      if (blank(lines[k]) || !numeric_row(lines[k], delim, decimal, &n) || n < 2) continue;
      bool run = true;
      for (std::size_t j = k + 1, seen = 1; j < lines.size() && seen < 8 && run; ++j) {
        if (blank(lines[j])) continue;
        std::size_t m = 0;
        run = numeric_row(lines[j], delim, decimal, &m) && m == n;
        ++seen;
      }
      if (!run) continue;
      std::size_t h = k - 1;
      while (h > 0 && blank(lines[h])) --h;
      if (blank(lines[h]) || header_columns(lines[h], delim) != n || !names_row(lines[h], delim)) {
        break;  // the numeric rows start without a header: not this dialect's layout
      }
      if (!best || n > best->columns) best = Dialect{delim, decimal, static_cast<int>(h), n};
      break;
    }
  }
  return best;
}

// "; the file looks like ';'-separated with decimal comma: set data.delimiter: ";" and
// data.decimal: ","", or "" when the file does not look like another dialect than `used`.
std::string dialect_hint(std::string_view text, const Dialect& used) {
  const auto d = sniff(head_lines(text));
  if (!d || (d->delimiter == used.delimiter && d->decimal == used.decimal &&
             d->skip_lines == used.skip_lines)) {
    return "";
  }
  std::string what = delimiter_word(d->delimiter) + "-separated with decimal " +
                     (d->decimal == ',' ? "comma" : "point");
  if (d->skip_lines > 0) what += ", header on line " + std::to_string(d->skip_lines + 1);
  std::vector<std::string> keys = {"data.delimiter: " + delimiter_yaml(d->delimiter)};
  if (d->decimal != '.' || d->decimal != used.decimal) {
    keys.push_back(std::string("data.decimal: \"") + d->decimal + "\"");
  }
  if (d->skip_lines != used.skip_lines) {
    keys.push_back("data.skip_lines: " + std::to_string(d->skip_lines));
  }
  std::string set;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    set += (i == 0 ? "" : i + 1 == keys.size() ? " and " : ", ") + keys[i];
  }
  return "; the file looks like " + what + ": set " + set;
}

// data.delimiter absent: the first of tab, ';', ',' that splits the header into two or more
// cells and the next (up to 5) rows into as many; ',' (';' with a decimal comma) otherwise.
char detect_delimiter(std::string_view header, std::string_view rest, char decimal) {
  std::array<std::string_view, 5> rows{};
  std::size_t nrows = 0, pos = 0;
  while (nrows < rows.size() && pos < rest.size()) {
    std::size_t eol = rest.find('\n', pos);
    if (eol == std::string_view::npos) eol = rest.size();
    const std::string_view line = without_cr(rest.substr(pos, eol - pos));
    if (!blank(line)) rows[nrows++] = line;
    pos = eol + 1;
  }
  for (const char d : {'\t', ';', ','}) {
    if (d == ',' && decimal == ',') continue;
    // Cells counted both with and without an empty last one (rows ending in the delimiter) and
    // a LabVIEW Comment column.
    std::vector<std::string_view> cells;
    split_cells(header, d, cells, false);
    const std::size_t n_raw = cells.size(), n = header_columns(header, d);
    if (n < 2 && n_raw < 2) continue;
    bool same = true;
    for (std::size_t i = 0; i < nrows && same; ++i) {
      split_cells(rows[i], d, cells, false);
      same = cells.size() == n_raw || cells_in(rows[i], d) == n;
    }
    if (same) return d;
  }
  return decimal == ',' ? ';' : ',';
}

std::string header_without_unit(const std::string& header) {
  std::string s = header;
  while (!s.empty() && s.back() == ' ') s.pop_back();
  if (!s.empty() && (s.back() == ')' || s.back() == ']')) {
    const char open = s.back() == ')' ? '(' : '[';
    const std::size_t o = s.rfind(open);
    if (o != std::string::npos && o > 0) s.erase(o);
  }
  while (!s.empty() && (s.back() == ' ' || s.back() == '_')) s.pop_back();
  return lower(s);
}

}  // namespace

bool is_text_signal_file(const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  return ext == ".csv" || ext == ".txt" || ext == ".tsv" || ext == ".lvm";
}

namespace {

bool is_uff_file(const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  return ext == ".uff" || ext == ".unv";
}

bool is_mat_file(const std::filesystem::path& file) {
  return lower(file.extension().string()) == ".mat";
}

// The readers of app/formats name the file by its path; messages here start with the label.
[[noreturn]] void rethrow_labelled(const InputError& e, const std::filesystem::path& file,
                                   const std::string& label) {
  std::string what = e.what();
  const std::string path = file.string();
  if (what.compare(0, path.size(), path) == 0) what = label + what.substr(path.size());
  throw InputError(what);
}

std::string sig6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

void check_finite(const std::vector<double>& c, const std::string& name, const std::string& label) {
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(c[i])) {
      throw InputError(label + ": " + (std::isnan(c[i]) ? "NaN" : "infinite") + " value at " +
                       sample_where(i, name));
    }
  }
}

}  // namespace

bool is_signal_file(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".f32" || ext == ".f64" || is_text_signal_file(file) || is_uff_file(file) ||
         is_mat_file(file);
}

SignalTable::SignalTable(SignalTable&&) noexcept = default;
SignalTable& SignalTable::operator=(SignalTable&&) noexcept = default;
SignalTable::~SignalTable() = default;

SignalTable SignalTable::open(const DataSpec& data, const std::string& label) {
  const double sample_rate_hz = data.sample_rate_hz;
  SignalTable t;
  t.label_ = label;
  // Only a regular file is opened (a FIFO would block; app/core/input_boundary.h).
  if (data.file.empty()) throw InputError(label + ": file not found");
  if (const std::string why = regular_file_problem(data.file); !why.empty()) {
    throw InputError(label + ": " + why);
  }
  const auto ext = data.file.extension().string();
  if (ext == ".f32" || ext == ".f64") {
    t.value_bytes_ = ext == ".f32" ? 4 : 8;
    t.names_ = data.channels;
    if (t.names_.empty()) throw InputError(label + ": data.channels is required for raw files");
    if (t.names_.size() > kMaxChannels) {
      throw InputError(label + ": data.channels names " + std::to_string(t.names_.size()) +
                       " channels, more than the " + std::to_string(kMaxChannels) +
                       " a signal file may have");
    }
    t.mapped_ = std::make_unique<MappedFile>(data.file, label);
    const std::size_t frame = t.names_.size() * static_cast<std::size_t>(t.value_bytes_);
    if (t.mapped_->size() % frame != 0) {
      throw InputError(label + ": size " + std::to_string(t.mapped_->size()) +
                       " bytes is not a multiple of " + std::to_string(t.names_.size()) +
                       " channels x " + std::to_string(t.value_bytes_) +
                       " bytes (truncated file or wrong data.channels)");
    }
    t.samples_ = t.mapped_->size() / frame;
    // One sequential pass for NaN/Inf so that a bad sample is reported at load time.
    const char* p = t.mapped_->data();
    const std::size_t nch = t.names_.size();
    for (std::size_t i = 0; i < t.samples_ * nch; ++i) {
      const double v = t.value_bytes_ == 4 ? load_le<float>(p + 4 * i) : load_le<double>(p + 8 * i);
      if (!std::isfinite(v)) {
        throw InputError(label + ": " + (std::isnan(v) ? "NaN" : "infinite") + " value at " +
                         sample_where(i / nch, t.names_[i % nch]));
      }
    }
  } else if (is_text_signal_file(data.file)) {
    t.read_text(data);
  } else if (is_uff_file(data.file)) {
    t.read_uff(data);
  } else if (is_mat_file(data.file)) {
    t.read_mat(data);
  } else {
    throw InputError(label + ": unsupported signal format '" + ext +
                     "' (use text .csv, .txt, .tsv, .lvm, raw .f32, .f64, UFF .uff, .unv or "
                     "MATLAB .mat)");
  }
  if (t.samples_ == 0) throw InputError(label + ": no samples");
  // Record 7 prints dx with 6 significant digits (E13.5): 1e-5 covers its rounding.
  if (sample_rate_hz > 0 && t.file_rate_hz_ > 0 &&
      std::abs(t.file_rate_hz_ - sample_rate_hz) > 1e-5 * sample_rate_hz) {
    char buf[320];
    std::snprintf(buf, sizeof(buf),
                  ": the records' abscissa step dx = %.6g s is %.6g Hz, test.yaml says "
                  "sample_rate_hz: %.6g; set sample_rate_hz: %.6g (or fix the file)",
                  1.0 / t.file_rate_hz_, t.file_rate_hz_, sample_rate_hz, t.file_rate_hz_);
    throw InputError(label + buf);
  }
  return t;
}

namespace {

// The rows after the header: one cell per column, each a finite number. Templated on the
// decimal mark so that the plain-CSV loop stays what it was (memchr for the delimiter,
// from_chars in place).
// A row ending in the delimiter (LabVIEW) has an empty last cell, which is not a column;
// quoted cells take the slower split_cells path. With `extra_ok` (a LabVIEW Comment column
// left out of the header), cells after the last column are ignored.
template <bool kDecimalComma, typename Fail>
void parse_rows(std::string_view text, std::size_t pos, std::size_t line_no, char delim,
                const std::vector<std::string>& names, std::vector<std::vector<double>>& columns,
                bool extra_ok, const Fail& fail) {
  const std::size_t nch = names.size();
  std::vector<std::string_view> quoted;
  while (pos < text.size()) {
    ++line_no;
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    const bool has_quotes = line.find('"') != std::string_view::npos;
    if (has_quotes) {
      split_cells(line, delim, quoted);
    } else {
      std::size_t end = line.size();
      while (end > 0 && line[end - 1] == ' ' && delim != ' ') --end;
      if (end > 1 && line[end - 1] == delim) line = line.substr(0, end - 1);
    }
    std::size_t cell = 0, cpos = 0;
    while (true) {
      const std::size_t d = has_quotes ? (cell + 1 < quoted.size() ? 0 : std::string_view::npos)
                                       : line.find(delim, cpos);
      std::string_view s =
          has_quotes
              ? quoted[cell]
              : line.substr(cpos, d == std::string_view::npos ? line.size() - cpos : d - cpos);
      if (cell >= nch) {
        if (extra_ok) break;
        fail("line " + std::to_string(line_no) + " has more than " + std::to_string(nch) +
             " cells (header has " + std::to_string(nch) + ")");
      }
      double v = 0;
      if (!to_double<kDecimalComma>(s, v)) {
        while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
        while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
        fail("line " + std::to_string(line_no) + ", column '" + names[cell] + "': '" +
             std::string(s) + "' is not a number");
      }
      if (!std::isfinite(v)) {
        fail(std::string(std::isnan(v) ? "NaN" : "infinite") + " value at line " +
             std::to_string(line_no) + ", column '" + names[cell] + "'");
      }
      columns[cell].push_back(v);
      ++cell;
      if (d == std::string_view::npos) break;
      cpos = d + 1;
    }
    if (cell != nch) {
      fail("line " + std::to_string(line_no) + " has " + std::to_string(cell) +
           " cells, the header has " + std::to_string(nch) + " (ragged row)");
    }
  }
}

}  // namespace

void SignalTable::read_text(const DataSpec& data) {
  const std::string& label = label_;
  if (data.decimal != '.' && data.decimal != ',') {
    throw InputError(label + ": data.decimal must be \".\" or \",\"");
  }
  if (data.delimiter != 0 && data.delimiter != ',' && data.delimiter != ';' &&
      data.delimiter != '\t') {
    throw InputError(label + ": data.delimiter must be \",\", \";\" or tab");
  }
  if (data.delimiter == ',' && data.decimal == ',') {
    throw InputError(label + ": data.decimal \",\" needs data.delimiter \";\" or tab");
  }
  MappedFile f(data.file, label);
  std::string_view text(f.data() ? f.data() : "", f.size());
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark

  Dialect used;
  used.decimal = data.decimal;
  used.skip_lines = data.skip_lines;
  // Every parse error ends with the dialect the file looks like, when it is another one.
  const auto fail = [&](const std::string& what) {
    throw InputError(label + ": " + what + dialect_hint(text, used));
  };

  std::size_t pos = 0;
  for (int i = 0; i < data.skip_lines; ++i) {
    const std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) {
      throw InputError(label + ": data.skip_lines is " + std::to_string(data.skip_lines) +
                       " but the file has only " + std::to_string(i + (pos < text.size())) +
                       " lines");
    }
    pos = nl + 1;
  }
  const std::size_t line_end = text.find('\n', pos);
  const std::string_view header = without_cr(text.substr(
      pos, line_end == std::string_view::npos ? std::string_view::npos : line_end - pos));
  const std::size_t body = line_end == std::string_view::npos ? text.size() : line_end + 1;
  const char delim = data.delimiter != 0
                         ? data.delimiter
                         : detect_delimiter(header, text.substr(body), data.decimal);
  delimiter_ = delim;
  used.delimiter = delim;

  std::vector<std::string_view> cells;
  split_cells(header, delim, cells);
  if (cells.size() > kMaxChannels + 1) {  // + 1: LabVIEW's trailing Comment column
    fail("the header has " + std::to_string(cells.size()) + " columns, more than the " +
         std::to_string(kMaxChannels) + " channels a signal file may have");
  }
  for (auto c : cells) {
    // Quotes are gone (split_cells); blanks around a name are not part of it.
    while (!c.empty() && (c.front() == ' ' || c.front() == '\t')) c.remove_prefix(1);
    while (!c.empty() && (c.back() == ' ' || c.back() == '\t')) c.remove_suffix(1);
    std::string name(c);
    for (std::size_t q = name.find("\"\""); q != std::string::npos; q = name.find("\"\"", q + 1)) {
      name.erase(q, 1);  // "" inside a quoted header cell
    }
    names_.push_back(std::move(name));
  }
  // LabVIEW's measurement files end the header with a Comment column that rows leave empty.
  const bool comment_column = names_.size() > 1 && comment_cell(names_.back());
  if (comment_column) names_.pop_back();
  if (names_.size() > kMaxChannels) {
    fail("the header has " + std::to_string(names_.size()) + " columns, more than the " +
         std::to_string(kMaxChannels) + " channels a signal file may have");
  }
  if (names_.size() == 1 && names_[0].empty()) {
    if (data.skip_lines > 0) {
      fail("line " + std::to_string(data.skip_lines + 1) +
           " (after data.skip_lines) is empty: a header row of channel names is required there");
    }
    fail("empty file (a header row of channel names is required)");
  }
  for (const auto& n : names_) {
    if (!n.empty() && number_in(n, data.decimal)) {
      fail((data.skip_lines > 0 ? "line " + std::to_string(data.skip_lines + 1) + ", the header "
                                : std::string("first ")) +
           "row must be a header of channel names, got '" + n + "'");
    }
  }
  const std::size_t nch = names_.size();
  columns_.assign(nch, {});
  for (auto& c : columns_) c.reserve(text.size() / (nch * 12) + 1);
  const std::size_t header_line = static_cast<std::size_t>(data.skip_lines) + 1;
  if (data.decimal == ',') {
    parse_rows<true>(text, body, header_line, delim, names_, columns_, comment_column, fail);
  } else {
    parse_rows<false>(text, body, header_line, delim, names_, columns_, comment_column, fail);
  }
  samples_ = columns_[0].size();
}

void SignalTable::read_uff(const DataSpec& data) {
  std::vector<uff::Function58> functions;
  try {
    functions = uff::read_uff58(data.file);
  } catch (const InputError& e) {
    rethrow_labelled(e, data.file, label_);
  }
  std::vector<std::string> others;
  const uff::Function58* first = nullptr;
  for (std::size_t k = 0; k < functions.size(); ++k) {
    const auto& f = functions[k];
    const bool time = f.function_type == 0 || f.function_type == uff::kTimeResponse;
    if (!time || f.complex_ordinate || f.x.size() != 0) {
      others.push_back("#" + std::to_string(k + 1) + " '" + f.id1 + "' (function type " +
                       std::to_string(f.function_type) + (f.complex_ordinate ? ", complex" : "") +
                       (f.x.size() != 0 ? ", uneven abscissa" : "") + ")");
      continue;
    }
    const std::string where = "dataset 58 #" + std::to_string(k + 1) + " '" + f.id1 + "'";
    if (!first) {
      first = &f;
    } else if (f.dx != first->dx || f.samples() != first->samples()) {
      throw InputError(label_ + ": " + where + " has " + std::to_string(f.samples()) +
                       " samples at dx " + sig6(f.dx) + " s, the first time record '" + first->id1 +
                       "' " + std::to_string(first->samples()) + " at dx " + sig6(first->dx) +
                       " s: every channel must share both");
    }
    if (names_.size() == kMaxChannels) {
      throw InputError(label_ + ": more than " + std::to_string(kMaxChannels) +
                       " time records, the most channels a signal file may have");
    }
    std::string name = f.id1;
    if (name.empty() || index_of(name) >= 0) name = "record " + std::to_string(names_.size());
    names_.push_back(name);
    uff_records_.push_back(static_cast<int>(k + 1));
    columns_.emplace_back(f.real.data(), f.real.data() + f.real.size());
    check_finite(columns_.back(), name, label_);
  }
  if (!first) {
    throw InputError(label_ +
                     ": no dataset 58 time record (function type 1, real, even "
                     "abscissa) in the file" +
                     (others.empty() ? std::string() : "; it holds " + joined(others)));
  }
  samples_ = columns_[0].size();
  file_rate_hz_ = first->sample_rate_hz();
}

void SignalTable::read_mat(const DataSpec& data) {
  struct Candidate {
    std::string name, variable;
    std::optional<std::size_t> column;
    std::size_t length;
  };
  std::vector<Candidate> candidates;
  std::vector<std::string> left_out;
  try {
    for (const auto& v : mat::numeric_variables(data.file)) {
      const std::string base = lower(v.name);
      if (base == "t" || base == "time") {
        left_out.push_back(v.name + " (time)");
      } else if (v.complex) {
        left_out.push_back(v.name + " (complex)");
      } else if (v.rows * v.cols <= 1) {
        left_out.push_back(v.name + (v.rows * v.cols == 1 ? " (scalar)" : " (empty)"));
      } else if ((v.vector() ? 1 : v.cols) > kMaxChannels - candidates.size()) {
        throw InputError(data.file.string() + ": more than " + std::to_string(kMaxChannels) +
                         " channels (vectors and matrix columns; variable '" + v.name + "' is " +
                         std::to_string(v.rows) + " x " + std::to_string(v.cols) +
                         "), the most a signal file may have");
      } else if (v.vector()) {
        candidates.push_back({v.name, v.name, std::nullopt, v.rows * v.cols});
      } else {
        for (std::size_t k = 0; k < v.cols; ++k) {
          candidates.push_back({v.name + "(:," + std::to_string(k + 1) + ")", v.name, k, v.rows});
        }
      }
    }
    if (candidates.empty()) {
      throw InputError(data.file.string() + ": no real numeric vector or matrix variable" +
                       (left_out.empty() ? std::string(" (no numeric variable at all)")
                                         : " (left out: " + joined(left_out) + ")"));
    }
    // The record length: the one most channels share, the longest on a tie.
    std::map<std::size_t, std::size_t> count;
    for (const auto& c : candidates) ++count[c.length];
    std::size_t length = 0, most = 0;
    for (const auto& [n, k] : count) {
      if (k >= most) {
        length = n;
        most = k;
      }
    }
    // The variables holding channels, read in one opening of the file.
    std::vector<std::string> wanted;
    for (const auto& c : candidates) {
      if (c.length == length &&
          std::find(wanted.begin(), wanted.end(), c.variable) == wanted.end()) {
        wanted.push_back(c.variable);
      }
    }
    const std::vector<Eigen::MatrixXd> loaded = mat::read_matrices(data.file, wanted);
    for (const auto& c : candidates) {
      if (c.length != length) {
        left_out.push_back(c.name + " (" + std::to_string(c.length) + " values, the record has " +
                           std::to_string(length) + ")");
        continue;
      }
      const auto at = std::find(wanted.begin(), wanted.end(), c.variable) - wanted.begin();
      const Eigen::MatrixXd& m = loaded[static_cast<std::size_t>(at)];
      const bool fits = c.column ? m.cols() > static_cast<Eigen::Index>(*c.column) &&
                                       m.rows() >= static_cast<Eigen::Index>(length)
                                 : m.size() >= static_cast<Eigen::Index>(length);
      if (!fits) {  // listed and read apart: a damaged v7.3 file may answer differently
        throw InputError(data.file.string() + ": variable '" + c.variable + "' read as " +
                         std::to_string(m.rows()) + " x " + std::to_string(m.cols()) +
                         ", not the size its header lists (a damaged file)");
      }
      const double* p = c.column ? m.col(static_cast<Eigen::Index>(*c.column)).data() : m.data();
      names_.push_back(c.name);
      columns_.emplace_back(p, p + length);
      check_finite(columns_.back(), c.name, label_);
    }
  } catch (const InputError& e) {
    rethrow_labelled(e, data.file, label_);
  }
  if (!left_out.empty()) left_out_ = "; not channels: " + joined(left_out);
  mat_ = true;
  samples_ = columns_[0].size();
}

bool SignalTable::has(const std::string& name) const { return index_of(name) >= 0; }

int SignalTable::index_of(const std::string& name) const {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::size_t SignalTable::column_of(const std::string& name, const ChannelSpec& cal) const {
  if (cal.record) {
    const std::string key = "channels." + name + ".record";
    if (uff_records_.empty()) {
      throw InputError(label_ + ": " + key + " applies to .uff/.unv files; set channels." + name +
                       ".column to the header text of its column or its 0-based index");
    }
    std::string records;
    for (std::size_t i = 0; i < names_.size(); ++i) {
      if (uff_records_[i] == *cal.record) return i;
      records += (i ? ", " : "") + std::to_string(uff_records_[i]) + " '" + names_[i] + "'";
    }
    throw InputError(label_ + ": " + key + " is " + std::to_string(*cal.record) +
                     ": not a time record of the file (time records: " + records + ")");
  }
  if (cal.variable) {
    const std::string key = "channels." + name + ".variable";
    if (!mat_) {
      throw InputError(label_ + ": " + key + " applies to .mat files; set channels." + name +
                       ".column to " +
                       (delimiter_ != 0 ? "the header text of its column" : "its channel name") +
                       " or its 0-based index");
    }
    std::string target = *cal.variable;
    if (cal.column) {
      if (!cal.column->by_index()) {
        throw InputError(label_ + ": channels." + name + ".column '" + cal.column->header +
                         "': with " + key + " it must be the 0-based column of the matrix");
      }
      target += "(:," + std::to_string(cal.column->index + 1) + ")";
    }
    const int idx = index_of(target);
    if (idx >= 0) return static_cast<std::size_t>(idx);
    if (!cal.column && index_of(target + "(:,1)") >= 0) {
      throw InputError(label_ + ": " + key + " '" + target + "' is a matrix: set channels." + name +
                       ".column to its 0-based column");
    }
    throw InputError(label_ + ": " + key + " '" + *cal.variable + "'" +
                     (cal.column ? " column " + std::to_string(cal.column->index) : std::string()) +
                     " is not a channel of the file (channels: " + joined(names_, "'") + ")" +
                     left_out_);
  }
  if (!cal.column) {
    const int idx = index_of(name);
    if (idx < 0) {
      throw InputError(label_ + ": no channel named '" + name + "' (channels: " + joined(names_) +
                       ")" + left_out_);
    }
    return static_cast<std::size_t>(idx);
  }
  const ColumnRef& c = *cal.column;
  const std::string key = "channels." + name + ".column";
  if (c.by_index()) {
    if (static_cast<std::size_t>(c.index) < names_.size()) return static_cast<std::size_t>(c.index);
    throw InputError(label_ + ": " + key + " is " + std::to_string(c.index) +
                     ", out of range: the file has " + std::to_string(names_.size()) +
                     " columns, 0 to " + std::to_string(names_.size() - 1) + " (" + joined(names_) +
                     ")");
  }
  const int idx = index_of(c.header);
  if (idx >= 0) return static_cast<std::size_t>(idx);
  std::string hint;
  for (const auto& n : names_) {
    if (lower(n) == lower(c.header) || within_edits(n, c.header, 2)) {
      hint = " (did you mean '" + n + "'?)";
      break;
    }
  }
  const bool text = delimiter_ != 0;
  throw InputError(label_ + ": " + key + " '" + c.header + "' is not a " +
                   (text ? "column of the header (columns: " : "channel of the file (channels: ") +
                   joined(names_, "'") + ")" + hint + left_out_);
}

Eigen::VectorXd SignalTable::channel(const std::string& name, const ChannelSpec& cal) const {
  const std::size_t idx = column_of(name, cal);
  Eigen::VectorXd out(static_cast<Eigen::Index>(samples_));
  if (mapped_) {
    const std::size_t nch = names_.size();
    const char* p = mapped_->data();
    for (std::size_t i = 0; i < samples_; ++i) {
      const std::size_t k = i * nch + idx;
      const double raw = value_bytes_ == 4 ? load_le<float>(p + 4 * k) : load_le<double>(p + 8 * k);
      out[static_cast<Eigen::Index>(i)] = cal.scale * raw + cal.offset;
    }
  } else {
    const auto& c = columns_[idx];
    for (std::size_t i = 0; i < samples_; ++i) {
      out[static_cast<Eigen::Index>(i)] = cal.scale * c[i] + cal.offset;
    }
  }
  return out;
}

std::vector<std::string> missing_channels(const SignalTable& table,
                                          const std::vector<std::string>& required,
                                          const std::map<std::string, ChannelSpec>& channels,
                                          const std::string& what) {
  std::vector<std::string> out;
  const auto& names = table.names();
  std::set<std::size_t> claimed;
  std::vector<std::string> unresolved;
  for (const auto& name : required) {
    const auto it = channels.find(name);
    const ChannelSpec cal = it == channels.end() ? ChannelSpec{} : it->second;
    if (!cal.column && !cal.record && !cal.variable && !table.has(name)) {
      unresolved.push_back(name);
      continue;
    }
    try {
      claimed.insert(table.column_of(name, cal));
    } catch (const InputError& e) {
      out.push_back(e.what());
    }
  }
  // Columns no required channel uses, a time column apart: the candidates to map.
  std::vector<std::string> free;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string base = header_without_unit(names[i]);
    if (claimed.count(i) || base == "t" || base == "time" || names[i].empty()) continue;
    if (std::find(required.begin(), required.end(), names[i]) != required.end()) continue;
    free.push_back(names[i]);
  }
  for (const auto& name : unresolved) {
    std::string msg = table.label() + ": channel '" + name + "' is required for " + what +
                      " (channels: " + joined(names) + ")";
    std::vector<std::string> same;
    for (const auto& n : free) {
      if (header_without_unit(n) == lower(name)) same.push_back(n);
    }
    const std::string key = "channels." + name + ".column";
    if (same.size() == 1) {
      msg += "; the column '" + same[0] + "' looks like it: set " + key + ": \"" + same[0] +
             "\" (units in headers are not read: add a scale when the unit is not the one the "
             "test needs)";
    } else if (!free.empty()) {
      msg += "; set " + key + " to the " +
             (table.delimiter() != 0 ? "header text of its column" : "name of its channel") + " (" +
             joined(free, "'") + ") or its 0-based index";
    }
    out.push_back(msg);
  }
  return out;
}

std::vector<std::string> unmatched_channel_keys(const SignalTable& table,
                                                const std::vector<std::string>& required,
                                                const std::map<std::string, ChannelSpec>& channels,
                                                const std::string& yaml_label) {
  std::vector<std::string> out;
  std::vector<std::string> known = table.names();
  known.insert(known.end(), required.begin(), required.end());
  for (const auto& [name, cal] : channels) {
    if (cal.column || cal.record || cal.variable) continue;  // mapped: checked by column_of
    if (table.has(name) || std::find(required.begin(), required.end(), name) != required.end()) {
      continue;
    }
    std::string best;
    int best_d = 1 << 20;
    for (const auto& k : known) {
      if (!looks_like(k, name) && lower(k) != lower(name)) continue;
      const int d = edit_distance(lower(k), lower(name));
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    std::string msg = yaml_label + ": key 'channels." + name + "' names no channel of " +
                      table.label() + " (channels: " + joined(table.names()) +
                      ") and no channel the test uses: its calibration would be ignored";
    if (!best.empty()) msg += " (did you mean '" + best + "'?)";
    out.push_back(msg);
  }
  return out;
}

void write_signals(const std::filesystem::path& file, const std::vector<std::string>& names,
                   const std::vector<const Eigen::VectorXd*>& columns) {
  const auto ext = file.extension().string();
  const Eigen::Index n = columns.empty() ? 0 : columns[0]->size();
  std::ofstream out = open_for_writing(file);
  if (ext == ".csv") {
    for (std::size_t j = 0; j < names.size(); ++j) out << (j ? "," : "") << names[j];
    out << '\n';
    char buf[32];
    std::string line;
    for (Eigen::Index i = 0; i < n; ++i) {
      line.clear();
      for (std::size_t j = 0; j < columns.size(); ++j) {
        auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), (*columns[j])[i]);
        (void)ec;
        if (j) line += ',';
        line.append(buf, ptr);
      }
      line += '\n';
      out << line;
    }
  } else if (ext == ".f32" || ext == ".f64") {
    std::vector<char> frame(columns.size() * (ext == ".f32" ? 4 : 8));
    for (Eigen::Index i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < columns.size(); ++j) {
        if (ext == ".f32") {
          const float v = static_cast<float>((*columns[j])[i]);
          std::memcpy(frame.data() + 4 * j, &v, 4);
        } else {
          const double v = (*columns[j])[i];
          std::memcpy(frame.data() + 8 * j, &v, 8);
        }
      }
      out.write(frame.data(), static_cast<std::streamsize>(frame.size()));
    }
  } else {
    throw InputError(file.string() + ": unsupported signal format '" + ext + "'");
  }
  close_checked(out, file);
}

}  // namespace chatterlab::app

#include "app/core/signals.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>

#include "analysis/common/summary.h"

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

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '"'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '"'))
    s.remove_suffix(1);
  return std::string(s);
}

template <typename T>
double load_le(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // little-endian host (x86-64, aarch64)
  return static_cast<double>(v);
}

std::string sample_where(std::size_t i, const std::string& channel) {
  return "channel '" + channel + "', sample " + std::to_string(i);
}

}  // namespace

SignalTable::SignalTable(SignalTable&&) noexcept = default;
SignalTable& SignalTable::operator=(SignalTable&&) noexcept = default;
SignalTable::~SignalTable() = default;

SignalTable SignalTable::open(const DataSpec& data, const std::string& label) {
  SignalTable t;
  t.label_ = label;
  if (!std::filesystem::exists(data.file)) throw InputError(label + ": file not found");
  const auto ext = data.file.extension().string();
  if (ext == ".f32" || ext == ".f64") {
    t.value_bytes_ = ext == ".f32" ? 4 : 8;
    t.names_ = data.channels;
    if (t.names_.empty()) throw InputError(label + ": data.channels is required for raw files");
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
  } else if (ext == ".csv") {
    MappedFile f(data.file, label);
    std::string_view text(f.data() ? f.data() : "", f.size());
    std::size_t line_end = text.find('\n');
    std::string_view header = text.substr(0, line_end);
    std::size_t pos = 0;
    while (true) {
      const std::size_t comma = header.find(',', pos);
      t.names_.push_back(trim(header.substr(pos, comma - pos)));
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
    if (t.names_.empty() || (t.names_.size() == 1 && t.names_[0].empty())) {
      throw InputError(label + ": empty file (a header row of channel names is required)");
    }
    for (const auto& n : t.names_) {
      char* endp = nullptr;
      std::strtod(n.c_str(), &endp);
      if (!n.empty() && endp && *endp == '\0') {
        throw InputError(label + ": first row must be a header of channel names, got '" + n + "'");
      }
    }
    const std::size_t nch = t.names_.size();
    t.columns_.assign(nch, {});
    for (auto& c : t.columns_) c.reserve(text.size() / (nch * 12) + 1);
    std::size_t line_no = 1;
    pos = line_end == std::string_view::npos ? text.size() : line_end + 1;
    while (pos < text.size()) {
      ++line_no;
      std::size_t eol = text.find('\n', pos);
      if (eol == std::string_view::npos) eol = text.size();
      std::string_view line = text.substr(pos, eol - pos);
      pos = eol + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.empty()) continue;
      std::size_t cell = 0, cpos = 0;
      while (true) {
        const std::size_t comma = line.find(',', cpos);
        std::string_view s =
            line.substr(cpos, comma == std::string_view::npos ? line.size() - cpos : comma - cpos);
        if (cell >= nch) {
          throw InputError(label + ": line " + std::to_string(line_no) + " has more than " +
                           std::to_string(nch) + " cells (header has " + std::to_string(nch) + ")");
        }
        while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
        while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
        double v = 0;
        const char* b = s.data();
        const char* e = s.data() + s.size();
        if (!s.empty() && *b == '+') ++b;
        auto [ptr, err] = std::from_chars(b, e, v);
        if (s.empty() || err != std::errc() || ptr != e) {
          throw InputError(label + ": line " + std::to_string(line_no) + ", column '" +
                           t.names_[cell] + "': '" + std::string(s) + "' is not a number");
        }
        if (!std::isfinite(v)) {
          throw InputError(label + ": " + (std::isnan(v) ? "NaN" : "infinite") + " value at line " +
                           std::to_string(line_no) + ", column '" + t.names_[cell] + "'");
        }
        t.columns_[cell].push_back(v);
        ++cell;
        if (comma == std::string_view::npos) break;
        cpos = comma + 1;
      }
      if (cell != nch) {
        throw InputError(label + ": line " + std::to_string(line_no) + " has " +
                         std::to_string(cell) + " cells, the header has " + std::to_string(nch) +
                         " (ragged row)");
      }
    }
    t.samples_ = t.columns_[0].size();
  } else {
    throw InputError(label + ": unsupported signal format '" + ext + "' (use .csv, .f32, .f64)");
  }
  if (t.samples_ == 0) throw InputError(label + ": no samples");
  return t;
}

bool SignalTable::has(const std::string& name) const { return index_of(name) >= 0; }

int SignalTable::index_of(const std::string& name) const {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return static_cast<int>(i);
  }
  return -1;
}

Eigen::VectorXd SignalTable::channel(const std::string& name, const ChannelSpec& cal) const {
  const int idx = index_of(name);
  if (idx < 0) {
    std::string have;
    for (const auto& n : names_) have += (have.empty() ? "" : ", ") + n;
    throw InputError(label_ + ": no channel named '" + name + "' (channels: " + have + ")");
  }
  Eigen::VectorXd out(static_cast<Eigen::Index>(samples_));
  if (mapped_) {
    const std::size_t nch = names_.size();
    const char* p = mapped_->data();
    for (std::size_t i = 0; i < samples_; ++i) {
      const std::size_t k = i * nch + static_cast<std::size_t>(idx);
      const double raw = value_bytes_ == 4 ? load_le<float>(p + 4 * k) : load_le<double>(p + 8 * k);
      out[static_cast<Eigen::Index>(i)] = cal.scale * raw + cal.offset;
    }
  } else {
    const auto& c = columns_[static_cast<std::size_t>(idx)];
    for (std::size_t i = 0; i < samples_; ++i) {
      out[static_cast<Eigen::Index>(i)] = cal.scale * c[i] + cal.offset;
    }
  }
  return out;
}

void write_signals(const std::filesystem::path& file, const std::vector<std::string>& names,
                   const std::vector<const Eigen::VectorXd*>& columns) {
  const auto ext = file.extension().string();
  const Eigen::Index n = columns.empty() ? 0 : columns[0]->size();
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError(file.string() + ": cannot write");
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
  if (!out) throw InputError(file.string() + ": write failed");
}

}  // namespace chatterlab::app

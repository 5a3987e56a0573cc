// A kind's result as bytes and back, for the per-test cache of nightly runs
// (docs/nightly.md#the-per-test-cache). One function per struct lists its members,
//
//   template <class Ar> void fields(Ar& ar, TapHitInfo& h) { ar(h.time_s, h.peak_N, ...); }
//
// in the struct's own namespace (found by argument-dependent lookup), and serves both
// directions: BinaryWriter appends each member, BinaryReader reads them back in the same order.
// Numbers, enums, strings, std::vector, std::array, std::optional, std::pair, std::map,
// std::shared_ptr<const T> and Eigen matrices of any size are handled here.
//
// The bytes are the program's own: no version, no byte order, no portability. They are valid
// only for the executable that wrote them, which the cache keys guarantee (a key holds the
// SHA-256 of the program: app/nightly/cache_keys.h). A member left out of `fields` would be
// lost silently: LAYOUT_GUARD(T, bytes) in a fields function stops the build when the struct's
// size changes, so that whoever adds a member is sent to its list.
#pragma once

#include <Eigen/Core>
#include <array>
#include <complex>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab::app {

class BinaryWriter {
 public:
  template <class... T>
  void operator()(T&... v);
  void raw(const void* p, std::size_t n) { data_.append(static_cast<const char*>(p), n); }
  static constexpr bool kReading = false;
  std::string& data() { return data_; }

 private:
  std::string data_;
};

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& data) : data_(data) {}
  template <class... T>
  void operator()(T&... v);
  // @throws InputError when the bytes end before the value (a truncated cache entry)
  void raw(void* p, std::size_t n) {
    if (n > data_.size() - pos_) throw InputError("a cached result ends early (damaged cache)");
    std::memcpy(p, data_.data() + pos_, n);
    pos_ += n;
  }
  // A count read back, checked against the bytes left (a damaged count never allocates much).
  std::size_t count(std::size_t element_bytes) {
    std::uint64_t n = 0;
    raw(&n, sizeof n);
    if (element_bytes > 0 && n > (data_.size() - pos_) / element_bytes) {
      throw InputError("a cached result holds an impossible length (damaged cache)");
    }
    return static_cast<std::size_t>(n);
  }
  bool done() const { return pos_ == data_.size(); }
  static constexpr bool kReading = true;

 private:
  const std::string& data_;
  std::size_t pos_ = 0;
};

template <class T>
struct is_bulk : std::bool_constant<std::is_arithmetic_v<T> || std::is_enum_v<T>> {};
template <class T>
struct is_bulk<std::complex<T>> : std::true_type {};

template <class T>
inline constexpr bool is_bulk_v = is_bulk<T>::value;

// Numbers, enums, complex numbers: their bytes.
template <class Ar, class T, std::enable_if_t<is_bulk_v<T>, int> = 0>
void io(Ar& ar, T& v) {
  ar.raw(&v, sizeof v);
}

template <class Ar>
void write_count(Ar& ar, std::size_t n) {
  std::uint64_t c = n;
  ar.raw(&c, sizeof c);
}

inline void io(BinaryWriter& ar, std::string& s) {
  write_count(ar, s.size());
  ar.raw(s.data(), s.size());
}
inline void io(BinaryReader& ar, std::string& s) {
  s.resize(ar.count(1));
  if (!s.empty()) ar.raw(s.data(), s.size());
}

// A struct with a fields() function of its own.
template <class Ar, class T>
auto io(Ar& ar, T& s) -> decltype(fields(ar, s)) {
  return fields(ar, s);
}

template <class Ar, class T>
void io(Ar& ar, std::vector<T>& v);
template <class Ar, class T>
void io(Ar& ar, std::optional<T>& v);
template <class Ar, class A, class B>
void io(Ar& ar, std::pair<A, B>& v);
template <class Ar, class T, std::size_t N>
void io(Ar& ar, std::array<T, N>& v);
template <class Ar, class K, class V>
void io(Ar& ar, std::map<K, V>& v);
template <class Ar, class T>
void io(Ar& ar, std::shared_ptr<const T>& v);
template <class Ar, class S, int R, int C, int O, int MR, int MC>
void io(Ar& ar, Eigen::Matrix<S, R, C, O, MR, MC>& m);

template <class Ar, class T>
void io(Ar& ar, std::vector<T>& v) {
  if constexpr (Ar::kReading) {
    v.resize(ar.count(is_bulk_v<T> ? sizeof(T) : 1));
  } else {
    write_count(ar, v.size());
  }
  if constexpr (is_bulk_v<T>) {
    if (!v.empty()) ar.raw(v.data(), v.size() * sizeof(T));
  } else {
    for (auto& e : v) io(ar, e);
  }
}

// std::vector<bool> has no elements to take the address of.
template <class Ar>
void io(Ar& ar, std::vector<bool>& v) {
  if constexpr (Ar::kReading) {
    v.assign(ar.count(1), false);
  } else {
    write_count(ar, v.size());
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    bool b = v[i];
    io(ar, b);
    v[i] = b;
  }
}

template <class Ar, class T>
void io(Ar& ar, std::optional<T>& v) {
  bool has = v.has_value();
  io(ar, has);
  if constexpr (Ar::kReading) {
    if (has) {
      v.emplace();
    } else {
      v.reset();
    }
  }
  if (has) io(ar, *v);
}

template <class Ar, class A, class B>
void io(Ar& ar, std::pair<A, B>& v) {
  io(ar, v.first);
  io(ar, v.second);
}

template <class Ar, class T, std::size_t N>
void io(Ar& ar, std::array<T, N>& v) {
  for (auto& e : v) io(ar, e);
}

template <class Ar, class K, class V>
void io(Ar& ar, std::map<K, V>& v) {
  if constexpr (Ar::kReading) {
    const std::size_t n = ar.count(1);
    v.clear();
    for (std::size_t i = 0; i < n; ++i) {
      std::pair<K, V> e;
      io(ar, e);
      v.emplace(std::move(e));
    }
  } else {
    write_count(ar, v.size());
    for (auto& [k, val] : v) {
      K key = k;
      io(ar, key);
      io(ar, val);
    }
  }
}

// A shared value is stored by value: a reader gets its own copy (the pointers two results
// shared are not shared after a restore).
template <class Ar, class T>
void io(Ar& ar, std::shared_ptr<const T>& v) {
  bool has = v != nullptr;
  io(ar, has);
  if (!has) {
    if constexpr (Ar::kReading) v.reset();
    return;
  }
  if constexpr (Ar::kReading) {
    auto p = std::make_shared<T>();
    io(ar, *p);
    v = std::move(p);
  } else {
    io(ar, const_cast<T&>(*v));  // the writer only reads
  }
}

template <class Ar, class S, int R, int C, int O, int MR, int MC>
void io(Ar& ar, Eigen::Matrix<S, R, C, O, MR, MC>& m) {
  std::int64_t rows = m.rows(), cols = m.cols();
  io(ar, rows);
  io(ar, cols);
  if constexpr (Ar::kReading) {
    if (rows < 0 || cols < 0 ||
        (rows > 0 &&
         static_cast<std::uint64_t>(cols) > (1ull << 40) / static_cast<std::uint64_t>(rows))) {
      throw InputError("a cached result holds an impossible matrix size (damaged cache)");
    }
    if ((R != Eigen::Dynamic && rows != R) || (C != Eigen::Dynamic && cols != C)) {
      throw InputError("a cached result holds a matrix of another size (damaged cache)");
    }
    m.resize(rows, cols);
  }
  if (m.size() > 0) {
    if constexpr (is_bulk_v<S>) {
      ar.raw(m.data(), static_cast<std::size_t>(m.size()) * sizeof(S));
    } else {
      for (Eigen::Index i = 0; i < m.size(); ++i) io(ar, m.data()[i]);
    }
  }
}

template <class... T>
void BinaryWriter::operator()(T&... v) {
  (io(*this, v), ...);
}
template <class... T>
void BinaryReader::operator()(T&... v) {
  (io(*this, v), ...);
}

// The bytes of `v` (the writer only reads it).
template <class T>
std::string to_bytes(const T& v) {
  BinaryWriter w;
  io(w, const_cast<T&>(v));
  return std::move(w.data());
}

// `v` read back from bytes to_bytes wrote. @throws InputError when they do not hold one whole
// value (damaged)
template <class T>
void from_bytes(const std::string& bytes, T& v) {
  BinaryReader r(bytes);
  io(r, v);
  if (!r.done()) throw InputError("a cached result is longer than its value (damaged cache)");
}

}  // namespace chatterlab::app

namespace chatterlab {

template <class Ar>
void fields(Ar& ar, StepSummary& s) {
  ar(s.status, s.message, s.details, s.warnings);
}

}  // namespace chatterlab

// In a fields() function: the build stops when the struct's size is not `bytes` on x86-64, so
// that a member added to the struct is also added to its list.
#if defined(__x86_64__) && defined(__GLIBCXX__)
#define LAYOUT_GUARD(T, bytes)                                      \
  static_assert(sizeof(T) == (bytes), "the size of " #T             \
                                      " changed: list its members " \
                                      "in its fields() and update this guard")
#else
#define LAYOUT_GUARD(T, bytes) static_assert(true)
#endif

// Values as bytes, appended in order and read back in the same order: messages between workers and checkpoint states.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace gdp::schedule {

using Bytes = std::vector<unsigned char>;

// Thrown by ByteReader when the bytes end early, hold an impossible length or run on too long.
class CorruptState : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One function template given a ByteWriter or a ByteReader writes a state and reads it back:
// io(v) appends v / reads it back (a vector with its length); io_sized(v) a buffer of a known
// size (a ring or plane), written as io() writes a vector; put / get: n values, no length.
class ByteWriter {
 public:
  template <class V>
  void put(const V* p, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<V>);
    const std::size_t at = bytes.size();
    bytes.resize(at + n * sizeof(V));
    if (n) std::memcpy(bytes.data() + at, p, n * sizeof(V));
  }
  template <class V>
  void io(const V& v) {
    put(&v, 1);
  }
  template <class V>
  void io(const std::vector<V>& v) {
    io_sized(std::span<const V>(v));
  }
  template <class V>
  void io_sized(std::span<V> v) {
    io(static_cast<std::uint64_t>(v.size()));
    put(v.data(), v.size());
  }
  Bytes bytes;
};

class ByteReader {
 public:
  explicit ByteReader(Bytes bytes) : bytes_(std::move(bytes)) {}
  template <class V>
  void get(V* p, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<V>);
    if (n > (bytes_.size() - at_) / sizeof(V)) throw CorruptState("it ends early");
    if (n) std::memcpy(p, bytes_.data() + at_, n * sizeof(V));
    at_ += n * sizeof(V);
  }
  template <class V>
  void io(V& v) {
    get(&v, 1);
  }
  template <class V>
  void io(std::vector<V>& v) {
    std::uint64_t n = 0;
    io(n);
    if (n > (bytes_.size() - at_) / sizeof(V)) throw CorruptState("a length runs past the end");
    v.resize(n);
    get(v.data(), n);
  }
  template <class V>
  void io_sized(std::span<V> v) {
    std::uint64_t n = 0;
    io(n);
    if (n != v.size()) throw CorruptState("a buffer has the wrong size");
    get(v.data(), n);
  }
  bool at_end() const { return at_ == bytes_.size(); }
  void finish() const {
    if (!at_end()) throw CorruptState("it is longer than expected");
  }

 private:
  Bytes bytes_;
  std::size_t at_ = 0;
};

}  // namespace gdp::schedule

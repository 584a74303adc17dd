// Binary state blobs for checkpoints: plain values and vectors appended in order, read back in the same order.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace gdp::schedule {

// Thrown by StateReader when a blob ends early or holds an impossible length.
class CorruptState : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A state is written and read back by one function template given a StateWriter or a
// StateReader: io(v) appends v / reads it back; io_sized(v) reads a vector that must keep its
// present size (a ring or plane of a known shape).
class StateWriter {
 public:
  template <class V>
  void io(const V& v) {
    static_assert(std::is_trivially_copyable_v<V>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(V));
  }
  template <class V>
  void io(const std::vector<V>& v) {
    static_assert(std::is_trivially_copyable_v<V>);
    io(static_cast<std::uint64_t>(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(V));
  }
  template <class V>
  void io_sized(const std::vector<V>& v) {
    io(v);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  explicit StateReader(std::string bytes) : bytes_(std::move(bytes)) {}
  template <class V>
  void io(V& v) {
    static_assert(std::is_trivially_copyable_v<V>);
    take(&v, sizeof(V));
  }
  template <class V>
  void io(std::vector<V>& v) {
    std::uint64_t n = 0;
    io(n);
    if (n > (bytes_.size() - at_) / sizeof(V)) throw CorruptState("a length runs past the end");
    v.resize(n);
    take(v.data(), n * sizeof(V));
  }
  template <class V>
  void io_sized(std::vector<V>& v) {
    const std::size_t want = v.size();
    io(v);
    if (v.size() != want) throw CorruptState("a buffer has the wrong size");
  }
  bool at_end() const { return at_ == bytes_.size(); }

 private:
  void take(void* out, std::size_t n) {
    if (n > bytes_.size() - at_) throw CorruptState("it ends early");
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  std::string bytes_;
  std::size_t at_ = 0;
};

}  // namespace gdp::schedule

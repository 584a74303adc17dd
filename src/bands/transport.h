// How the workers of a band solve talk: point-to-point messages, one interface for threads and MPI.
#pragma once

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "schedule/parallel.h"

namespace gdp::bands {

using Bytes = std::vector<unsigned char>;

// Thrown by a transport's calls once any worker has stopped the solve (abort()); what() says
// which worker stopped it and why.
using TransportStopped = schedule::Stopped;

// One worker's end. Workers are numbered 0 .. size() - 1 (worker b solves band b). Sends
// never wait for the receiver; messages from one worker to another with the same tag arrive
// in the order they were sent.
class Transport {
 public:
  virtual ~Transport() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Starts sending `data` to worker `to` and returns (the transport keeps the bytes).
  virtual void send(int to, int tag, Bytes data) = 0;
  // The next message from worker `from` with `tag`, waiting until it has arrived.
  virtual Bytes receive(int from, int tag) = 0;
  // Stops every worker: their pending and later calls throw TransportStopped(why).
  virtual void abort(const std::string& why) = 0;
};

// A message as bytes: values appended in order (Packer), read back in the same order (Unpacker).
class Packer {
 public:
  template <class V>
  void put(const V* p, std::size_t n) {
    const std::size_t at = bytes.size();
    bytes.resize(at + n * sizeof(V));
    if (n) std::memcpy(bytes.data() + at, p, n * sizeof(V));
  }
  void put(double v) { put(&v, 1); }
  // A vector with its length.
  template <class V>
  void put(const std::vector<V>& v) {
    put(static_cast<double>(v.size()));
    put(v.data(), v.size());
  }
  Bytes bytes;
};

class Unpacker {
 public:
  explicit Unpacker(Bytes b) : b_(std::move(b)) {}
  template <class V>
  void get(V* p, std::size_t n) {
    if (at_ + n * sizeof(V) > b_.size()) throw std::logic_error("band message shorter than expected");
    if (n) std::memcpy(p, b_.data() + at_, n * sizeof(V));
    at_ += n * sizeof(V);
  }
  double get() {
    double v;
    get(&v, 1);
    return v;
  }
  // A vector Packer::put(const std::vector&) wrote.
  template <class V>
  void get(std::vector<V>& v) {
    v.resize(static_cast<std::size_t>(get()));
    get(v.data(), v.size());
  }
  void finish() const {
    if (at_ != b_.size()) throw std::logic_error("band message longer than expected");
  }

 private:
  Bytes b_;
  std::size_t at_ = 0;
};

// The collectives, over the members 0, step, 2 step, ... of `net` (every worker, or the first
// worker of every rank). gather(): worker 0 gets every member's message in member order (its own
// first), the others send theirs and get nothing. broadcast(): every member gets worker 0's
// `reply`. A gather, what worker 0 makes of it, and a broadcast are the one ordered reduction:
// the same bits however the members are spread over threads and ranks.
inline std::vector<Bytes> gather(Transport& net, int tag, Bytes mine, int step = 1) {
  if (net.rank() != 0) {
    net.send(0, tag, std::move(mine));
    return {};
  }
  std::vector<Bytes> all;
  all.push_back(std::move(mine));
  for (int m = step; m < net.size(); m += step) all.push_back(net.receive(m, tag));
  return all;
}
inline Bytes broadcast(Transport& net, int tag, Bytes reply, int step = 1) {
  if (net.rank() != 0) return net.receive(0, tag);
  for (int m = step; m < net.size(); m += step) net.send(m, tag, reply);
  return reply;
}

// Every member's `v` becomes the elementwise sum of all members' `v`, added in member order.
inline void sum_in_order(Transport& net, int tag, std::vector<double>& v, int step = 1) {
  Packer mine;
  mine.put(v.data(), v.size());
  std::vector<Bytes> parts = gather(net, tag, std::move(mine.bytes), step);
  std::vector<double> part(v.size());
  for (std::size_t m = 1; m < parts.size(); ++m) {
    Unpacker u(std::move(parts[m]));
    u.get(part.data(), part.size());
    u.finish();
    for (std::size_t i = 0; i < v.size(); ++i) v[i] += part[i];
  }
  Packer sum;
  sum.put(v.data(), v.size());
  Unpacker u(broadcast(net, tag, std::move(sum.bytes), step));
  u.get(v.data(), v.size());
  u.finish();
}

}  // namespace gdp::bands

// How the workers of a band solve talk: point-to-point messages, one interface for threads and MPI.
#pragma once

#include <cstddef>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "schedule/bytes.h"
#include "schedule/parallel.h"
#include "util/bells.h"

namespace gdp::bands {

using schedule::ByteReader;
using schedule::ByteWriter;
using schedule::Bytes;

class ThreadHub;

// One worker's end of a hub, or a view of every other worker (a merged stage). Workers are numbered
// 0 .. size() - 1 (worker b solves band b). Sends never wait for the receiver; messages from one
// worker to another with the same tag arrive in the order they were sent.
class Transport {
 public:
  Transport(ThreadHub& hub, int rank, int size, int stride = 1, int tags = 0)
      : hub_(&hub), rank_(rank), size_(size), stride_(stride), tags_(tags) {}
  int rank() const { return rank_; }
  int size() const { return size_; }
  // Starts sending `data` to worker `to` and returns (the transport keeps the bytes).
  void send(int to, int tag, Bytes data);
  // The next message from worker `from` with `tag`, waiting until it has arrived.
  Bytes receive(int from, int tag);
  // Workers 0, 2, 4, ... of this view as `size` workers of their own, tags moved by `tags`.
  Transport every_other(int size, int tags) const { return {*hub_, rank_ / 2, size, 2 * stride_, tags_ + tags}; }

 private:
  ThreadHub* hub_;
  int rank_, size_, stride_, tags_;  // worker w of this view is the hub's worker w * stride_
};

// The mailboxes of `size` workers, threads of one process. endpoint(b) is worker b's Transport
// (one thread each).
class ThreadHub {
 public:
  explicit ThreadHub(int size) : ThreadHub(size, 0, size) {}
  virtual ~ThreadHub() = default;
  int first() const { return first_; }  // the first worker of this process
  Transport& endpoint(int worker);       // worker in [first(), first() + local)
  Transport& own() { return endpoint(first_); }  // this process's first worker's (its collectives)
  void send(int from, int to, int tag, Bytes data);
  Bytes receive(int from, int to, int tag);
  // Stops every worker: their waiting and later calls throw util::Stopped(why).
  virtual void stop(const std::string& why);

 protected:
  // Workers [first, first + local) of `size` run in this process; messages to and from the others
  // go through send_away and receive_away (MpiHub, mpi_transport.h).
  ThreadHub(int local, int first, int size);
  virtual void send_away(int from, int to, int tag, Bytes data);
  virtual Bytes receive_away(int from, int to, int tag);
  const int local_, first_;

 private:
  bool here(int worker) const { return worker >= first_ && worker < first_ + local_; }

  // A receiver waits on its own box: a send wakes only the worker waiting for that message, after
  // unlocking (util/bells.h).
  struct Box {
    std::deque<Bytes> messages;
    util::Bells::Line waiting;
  };
  mutable std::mutex mutex_;
  util::Bells bells_;
  std::map<std::tuple<int, int, int>, Box> boxes_;  // (from, to, tag)
  std::optional<std::string> stopped_;
  std::vector<Transport> endpoints_;
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

// Every member's `mine`, in member order, on every member (a gather and a broadcast of the lot):
// what each member makes of the list in order is the same bits wherever the members run.
inline std::vector<Bytes> all_gather(Transport& net, int tag, Bytes mine, int step = 1) {
  ByteWriter all;
  for (Bytes& part : gather(net, tag, std::move(mine), step)) all.io(part);
  ByteReader r(broadcast(net, tag, std::move(all.bytes), step));
  std::vector<Bytes> parts;
  while (!r.at_end()) r.io(parts.emplace_back());
  return parts;
}

// Every member's `v` becomes the elementwise sum of all members' `v`, added in member order.
inline void sum_in_order(Transport& net, int tag, std::vector<double>& v) {
  ByteWriter mine;
  mine.io(v);
  std::vector<double> part;
  const std::vector<Bytes> parts = all_gather(net, tag, std::move(mine.bytes));
  for (std::size_t m = 0; m < parts.size(); ++m) {
    ByteReader(parts[m]).io(part);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = m == 0 ? part[i] : v[i] + part[i];
  }
}

}  // namespace gdp::bands

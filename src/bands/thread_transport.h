// The shared-memory transport: workers are threads of one process exchanging messages in mailboxes.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <tuple>

#include "bands/transport.h"

namespace gdp::bands {

// The mailboxes of `size` workers. endpoint(b) is worker b's Transport (one thread each).
class ThreadHub {
 public:
  explicit ThreadHub(int size) : ThreadHub(size, 0, size) {}
  virtual ~ThreadHub() = default;
  int first() const { return first_; }  // the first worker of this process
  Transport& endpoint(int worker);       // worker in [first(), first() + local)
  void send(int from, int to, int tag, Bytes data);
  Bytes receive(int from, int to, int tag);
  virtual void stop(const std::string& why);  // every call now waiting, and every later one, throws

 protected:
  // Workers [first, first + local) of `size` run in this process; messages to and from the others
  // go through send_away and receive_away (MpiHub).
  ThreadHub(int local, int first, int size);
  virtual void send_away(int from, int to, int tag, Bytes data);
  virtual Bytes receive_away(int from, int to, int tag);
  const int local_, first_, size_;

 private:
  bool here(int worker) const { return worker >= first_ && worker < first_ + local_; }

  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::tuple<int, int, int>, std::deque<Bytes>> boxes_;  // (from, to, tag)
  std::optional<std::string> stopped_;
  std::vector<Transport> endpoints_;
};

}  // namespace gdp::bands

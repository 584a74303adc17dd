// The shared-memory transport: workers are threads of one process exchanging messages in mailboxes.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <tuple>

#include "bands/transport.h"

namespace gdp::bands {

// The mailboxes of `size` workers. endpoint(b) is worker b's Transport (one thread each).
class ThreadHub {
 public:
  explicit ThreadHub(int size);
  ~ThreadHub();
  Transport& endpoint(int worker);

 private:
  class Endpoint;
  friend class Endpoint;
  void post(int from, int to, int tag, Bytes data);
  Bytes take(int from, int to, int tag);
  void stop(const std::string& why);

  int size_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::tuple<int, int, int>, std::deque<Bytes>> boxes_;  // (from, to, tag)
  std::optional<std::string> stopped_;
  std::vector<std::unique_ptr<Endpoint>> endpoints_;
};

}  // namespace gdp::bands

// How the workers of a band solve talk: point-to-point messages, one interface for threads and MPI.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "gdp/errors.h"

namespace gdp::bands {

using Bytes = std::vector<unsigned char>;

// Thrown by a transport's calls once any worker has stopped the solve (abort()); what() says
// which worker stopped it and why.
class TransportStopped : public Error {
 public:
  using Error::Error;
};

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

}  // namespace gdp::bands

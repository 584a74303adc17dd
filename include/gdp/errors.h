// Typed errors thrown by the gdp library; the CLI turns them into messages and exit codes.
#pragma once

#include <stdexcept>
#include <string>

namespace gdp {

// Base of every error the library reports. what() is a complete one-line message.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An input file is missing, unreadable, or has content we cannot use.
class InputError : public Error {
 public:
  using Error::Error;
};

// An output file could not be written (nothing is left behind when this is thrown).
class OutputError : public Error {
 public:
  using Error::Error;
};

// Options or arguments are invalid or inconsistent with each other.
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace gdp

// Overloaded{lambdas...}: one visitor with a lambda per kind of argument.
#pragma once

namespace gdp::util {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};

}  // namespace gdp::util

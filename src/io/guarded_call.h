// The one setjmp() of gdp's calls into C libraries that report errors by longjmp() (libjpeg, libpng).
#pragma once

#include <csetjmp>
#include <type_traits>

namespace gdp::io {

// Runs `call()` with `jump` set to come back here. False when the library's error handler
// longjmp()ed to `jump` (keeping its message), or when `call` returns false; true otherwise.
// The longjmp skips the frames of `call` and of the library, so those hold no C++ objects with
// destructors: `call` is a lambda of library calls on plain data made before it.
template <class Call>
bool guarded(std::jmp_buf& jump, Call&& call) {
  if (setjmp(jump)) return false;
  if constexpr (std::is_same_v<decltype(call()), bool>) {
    return call();
  } else {
    call();
    return true;
  }
}

}  // namespace gdp::io

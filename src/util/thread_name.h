// Names the calling thread (as `perf`, `top -H` and /proc/PID/task/*/comm show it), for profiles by role.
#pragma once

#include <pthread.h>

namespace gdp::util {

// `name`: at most 15 characters (the kernel's limit; longer names are refused and ignored).
inline void name_thread(const char* name) { pthread_setname_np(pthread_self(), name); }

}  // namespace gdp::util

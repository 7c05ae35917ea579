// Background work yields the CPU to latency-critical threads: the robot's video work to its
// control loop and laser, the console's edge processing to its decoding and drawing. Linux: the
// nice value is per thread, and threads the caller starts later inherit it.
#pragma once

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace mostar {

// Lowers the calling thread's scheduling priority by `nice_increment` (nice +5 by default).
// Best effort: a failure leaves the priority as it was.
inline void LowerCurrentThreadPriority(int nice_increment = 5) {
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), nice_increment);
}

}  // namespace mostar

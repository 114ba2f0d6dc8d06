// Per-thread workspaces of the kernels, so that a warm call allocates nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fdcore {

// The calling thread's workspace of type W (a struct of std::vectors with resize(nb)), sized for nb bodies.
// Not inlined, so that a caller holds the address it returns: inlined, GCC recomputed the thread-local address
// at each use instead of keeping it (a call to __tls_get_addr each time in a shared library, 15 of them in
// kinematics_derivatives' loops; 2–3 % of solo12's contact derivatives).
template <class W>
[[gnu::noinline]] W& thread_workspace(int nb) {
  thread_local W w;
  w.resize(static_cast<size_t>(nb));
  return w;
}

// n doubles of the calling thread's scratch, starting on a 64-byte boundary (a cache line: the one-state solves'
// vectors of 8 doubles then split no line at the start of a row, whatever address malloc returned: measured
// on solo12's aba_derivatives, 9.1–10.4 µs from one process to the next without it). Valid until the thread's
// next call.
inline double* aligned_scratch(size_t n) {
  thread_local std::vector<double> buf;
  buf.resize(n + 8);
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(buf.data());
  return buf.data() + (64 - at % 64) % 64 / sizeof(double);
}

}  // namespace fdcore

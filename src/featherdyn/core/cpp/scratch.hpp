// Per-thread workspaces of the kernels, so that a warm call allocates nothing.
#pragma once

#include <vector>

namespace fdcore {

// The calling thread's workspace of type W (a struct of std::vectors with resize(nb)), sized for nb bodies.
template <class W>
inline W& thread_workspace(int nb) {
  thread_local W w;
  w.resize(static_cast<size_t>(nb));
  return w;
}

}  // namespace fdcore

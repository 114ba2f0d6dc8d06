// The binding's shared pieces (docs/architecture.md, "The glue"): the array types, the length checks that
// turn a wrong shape into a status, the overflow checks of results, and the rows of a batch on the thread pool.
#pragma once

#include <Python.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <optional>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <utility>

#include "buffer.hpp"
#include "checks.hpp"
#include "groups.hpp"
#include "model_view.hpp"
#include "thread_pool.hpp"

namespace fdcore {

namespace nb = nanobind;

using In = nb::ndarray<const double, nb::c_contig, nb::device::cpu>;
using Out = nb::ndarray<double, nb::c_contig, nb::device::cpu>;
using InC = nb::ndarray<const std::complex<double>, nb::c_contig, nb::device::cpu>;
using OutC = nb::ndarray<std::complex<double>, nb::c_contig, nb::device::cpu>;
using Ints = nb::ndarray<const std::int32_t, nb::c_contig, nb::device::cpu>;
using RowStatus = std::pair<std::int64_t, std::int64_t>;


template <class A>
void require_present(const A& x) {
  if (!x.is_valid()) throw nb::type_error("featherdyn.core: a required array argument is None");
}

template <class A>
void require_aligned(const A& x) {
  if (x.is_valid() && reinterpret_cast<std::uintptr_t>(x.data()) % alignof(typename A::Scalar) != 0)
    throw nb::type_error("featherdyn.core: arrays must be aligned (the Python wrapper copies unaligned ones)");
}

// One state: a 1-D array of length n. OK or a LENGTH status naming the argument.
template <class A>
std::int64_t vec(const A& x, size_t n, std::int64_t arg) {
  require_present(x);
  require_aligned(x);
  if (x.ndim() != 1 || x.shape(0) != n) return make_status(LENGTH, arg, x.ndim() == 1 ? x.shape(0) : -1);
  return OK;
}

// A batch input: (R, n) with R = N rows, or R = 1 broadcast to every row (declare.hpp: run_batch).
using fdgroup::Rows;

// An output (or a one-state f_ext) of exactly this shape.
template <class A>
std::int64_t exact_shape(const A& x, std::initializer_list<size_t> shape, std::int64_t arg = ARG_OUT) {
  require_present(x);
  require_aligned(x);
  bool same = x.ndim() == shape.size();
  size_t d = 0;
  for (size_t n : shape) same = same && x.shape(d++) == n;
  return same ? OK : make_status(LENGTH, arg, static_cast<std::int64_t>(x.size()));
}

#define FD_TRY(expr)                   \
  do {                                 \
    const std::int64_t s_ = (expr);    \
    if (s_ != OK) return s_;           \
  } while (0)
#define FD_TRY_ROWS(expr)                              \
  do {                                                 \
    const std::int64_t s_ = (expr);                    \
    if (s_ != OK) return RowStatus{-1, s_};            \
  } while (0)

// Run body(item) → status over `items` items on the pool, GIL released (when the calling thread holds it: not on
// an XLA thread, bind_jax.cpp); (first failing row, its status). An item is `group` consecutive rows; a failing
// body adds (row − first row of the item) << 60.
template <class F>
inline RowStatus for_rows(std::int64_t items, const F& body, std::int64_t group = 1) {
  std::mutex m;
  RowStatus first{-1, OK};
  {
    std::optional<nb::gil_scoped_release> release;
    if (PyGILState_Check()) release.emplace();
    std::shared_ptr<ThreadPool> pool = GlobalPool::instance().get();
    pool->parallel_for(items, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t g = begin; g < end; ++g) {
        const std::int64_t s = body(g);
        if (s != OK) {
          const std::int64_t r = g * group + (s >> 60), status = s & ((std::int64_t(1) << 60) - 1);
          std::lock_guard<std::mutex> lock(m);
          if (first.first < 0 || r < first.first) first = {r, status};
          return;  // the rest of this chunk is left undone: the call fails anyway
        }
      }
    });
  }
  return first;
}

// The batched group kernels for this CPU (bindings.cpp).
const fdgroup::GroupKernels& group_kernels();

// A result that finite input overflowed (products beyond float64's range): NONFINITE on the output,
// so the caller words it instead of returning inf or NaN.
// (the vectorised scan first, with this CPU's registers (finite_scan.inc): a talos mass matrix's 2 500 entries
// cost 1.3 µs through first_nonfinite's early exit, which does not vectorise, and 0.1 µs there)
inline std::int64_t finite_result(const double* x, std::int64_t n) {
  if (group_kernels().all_finite(x, n)) return OK;
  const std::int64_t k = first_nonfinite(x, n);
  return k < 0 ? OK : make_status(NONFINITE, ARG_OUT, k);
}

// Whether [a, a + na) and [b, b + nb) share memory (null: nothing to share).
inline bool overlaps(const double* a, std::int64_t na, const double* b, std::int64_t nb) {
  return a != nullptr && b != nullptr && a < b + nb && b < a + na;
}

// Rows in groups of the kernels' width on the pool. Every row is checked; a full group runs the
// Pack instantiation (lanes bit-identical to one state), the tail and any group whose packed run
// fails (a singular ABA lane) run row by row with the double instantiation, which names the row.
//   check(r) → status;  one(r) → status;  many: the group kernel
template <class Check, class One>
RowStatus for_row_groups(std::int64_t N, const Check& check, const One& one, fdgroup::GroupFn many,
                         const fdgroup::GroupArgs& args) {
  const std::int64_t W = group_kernels().width;
  return for_rows((N + W - 1) / W, [&](std::int64_t g) -> std::int64_t {
    const std::int64_t r0 = g * W, n = std::min(W, N - r0);
    for (std::int64_t r = r0; r < r0 + n; ++r) {
      const std::int64_t s = check(r);
      if (s != OK) return s + ((r - r0) << 60);  // the row within the group (see for_rows)
    }
    if (n == W && many(args, r0) == 0) return OK;
    for (std::int64_t r = r0; r < r0 + n; ++r) {
      const std::int64_t s = one(r);
      if (s != OK) return s + ((r - r0) << 60);
    }
    return OK;
  }, W);
}

}  // namespace fdcore

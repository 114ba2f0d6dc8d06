// Pack: PACK_WIDTH doubles processed together (GCC/Clang vector extensions), so that one instantiation
// of a kernel template runs W states per instruction. Each lane does exactly the IEEE operations
// of the one-state `double` instantiation in the same order (no reassociation, and the core is
// built with -ffp-contract=off so that no multiply-add is fused differently), and sin, cos and
// sqrt are the scalar library calls lane by lane: every lane is bit-identical to the one-state
// result. Comparisons give a lane mask (see lanes_le).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#if defined(_MSC_VER) && !defined(__clang__)
#error "featherdyn's core uses GCC/Clang vector extensions: on Windows build it with clang-cl (CMake -T ClangCL)"
#endif

namespace fdcore {

// The lanes: one vector register. Two doubles on the x86-64 baseline (SSE2), four where the
// translation unit is compiled for AVX2 (simd_avx2.cpp), eight for AVX-512 (simd_avx512.cpp);
// bindings.cpp picks the widest the CPU has at import.
// (Four doubles on SSE2 — two registers — measured slower than two: 1.3× vs 0.65× the
// one-state kernel's time per state on panda.)
#if defined(__AVX512F__)
constexpr int PACK_WIDTH = 8;
#elif defined(__AVX2__)
constexpr int PACK_WIDTH = 4;
#else
constexpr int PACK_WIDTH = 2;
#endif

struct Pack {
  typedef double V __attribute__((vector_size(8 * PACK_WIDTH)));
  V v;

  Pack() = default;
  Pack(double x) : v(V{} + x) {}  // NOLINT(google-explicit-constructor): scalars broadcast, as for double
  static Pack raw(V x) {
    Pack p;
    p.v = x;
    return p;
  }
  double operator[](int k) const { return v[k]; }
  void set(int k, double x) { v[k] = x; }

  Pack& operator+=(const Pack& o) { v += o.v; return *this; }
  Pack& operator-=(const Pack& o) { v -= o.v; return *this; }
  Pack& operator*=(const Pack& o) { v *= o.v; return *this; }
};

inline Pack operator+(const Pack& a, const Pack& b) { return Pack::raw(a.v + b.v); }
inline Pack operator-(const Pack& a, const Pack& b) { return Pack::raw(a.v - b.v); }
inline Pack operator*(const Pack& a, const Pack& b) { return Pack::raw(a.v * b.v); }
inline Pack operator/(const Pack& a, const Pack& b) { return Pack::raw(a.v / b.v); }
inline Pack operator-(const Pack& a) { return Pack::raw(-a.v); }

// (all_finite over doubles: checks.hpp)
// The same over Packs, every lane (no dependency chain, one pass in L1/L2).
inline bool all_finite(const Pack* x, size_t n) {
  typedef unsigned long long U __attribute__((vector_size(8 * PACK_WIDTH)));
  const U exponent = U{} + 0x7FF0000000000000ull, one = U{} + 0x0010000000000000ull;
  U carry = U{};
  for (size_t k = 0; k < n; ++k) carry |= (reinterpret_cast<U>(x[k].v) & exponent) + one;  // a vector cast: bits
  unsigned long long any = 0;
  for (int lane = 0; lane < PACK_WIDTH; ++lane) any |= carry[lane];
  return (any >> 63) == 0;
}

// {x[0][k], x[1][k], …}: element k of each lane's row, built in a register (one wide store after,
// instead of one narrow store per lane that the next wide load could not forward).
inline Pack load_lanes(const double* const* x, size_t k) {
#if defined(__AVX512F__)
  return Pack::raw(Pack::V{x[0][k], x[1][k], x[2][k], x[3][k], x[4][k], x[5][k], x[6][k], x[7][k]});
#elif defined(__AVX2__)
  return Pack::raw(Pack::V{x[0][k], x[1][k], x[2][k], x[3][k]});
#else
  return Pack::raw(Pack::V{x[0][k], x[1][k]});
#endif
}

// The transpose of W Packs in registers: r[j][l] becomes r[l][j], so that W entries of one lane are a Pack (one
// wide store into the lane's row, instead of W narrow loads and stores). log2 W rounds; round h pairs each r[i]
// with i & h == 0 with r[i + h] and swaps the h-blocks between them: afterwards
//     r[i][l] = (l & h) == 0 ? r[i][l] : r[i + h][l − h],    r[i + h][l] = (l & h) == 0 ? r[i][l + h] : r[i + h][l].
// Each round is two two-source shuffles with constant indices (GCC's __builtin_shuffle, Clang's
// __builtin_shufflevector); no arithmetic, so the values are moved, never changed.
namespace transpose_detail {
constexpr int low(int l, int h) { return (l & h) == 0 ? l : PACK_WIDTH + l - h; }       // r[i]'s new lane l
constexpr int high(int l, int h) { return (l & h) == 0 ? l + h : PACK_WIDTH + l; }      // r[i + h]'s
template <int h, int... l>
inline void swap_blocks(Pack& x, Pack& y, std::integer_sequence<int, l...>) {
  const Pack::V a = x.v, b = y.v;
#if defined(__clang__)
  x.v = __builtin_shufflevector(a, b, low(l, h)...);
  y.v = __builtin_shufflevector(a, b, high(l, h)...);
#else
  typedef long long M __attribute__((vector_size(8 * PACK_WIDTH)));
  x.v = __builtin_shuffle(a, b, M{low(l, h)...});
  y.v = __builtin_shuffle(a, b, M{high(l, h)...});
#endif
}
// every index a constant (a fold over i), so that the Packs stay in registers
template <int h, int... i>
inline void round(Pack* r, std::integer_sequence<int, i...>) {
  ((((i & h) == 0) ? swap_blocks<h>(r[i], r[i + h], std::make_integer_sequence<int, PACK_WIDTH>{})
                   : void()),
   ...);
}
template <int h>
inline void rounds(Pack* r) {
  if constexpr (h < PACK_WIDTH) {
    round<h>(r, std::make_integer_sequence<int, PACK_WIDTH>{});
    rounds<2 * h>(r);
  }
}
}  // namespace transpose_detail
inline void transpose_lanes(Pack* r) { transpose_detail::rounds<1>(r); }

#define FD_PACK_LANEWISE(fn)                              \
  inline Pack fn(const Pack& a) {                         \
    Pack r;                                               \
    for (int k = 0; k < PACK_WIDTH; ++k) r.set(k, std::fn(a[k]));     \
    return r;                                             \
  }
FD_PACK_LANEWISE(sin)
FD_PACK_LANEWISE(cos)
#undef FD_PACK_LANEWISE

// √x in one instruction for all lanes: IEEE 754's square root is correctly rounded, so each lane is std::sqrt's
// (the factors of ltl.hpp and aba.hpp take one per dof and per constraint row).
inline Pack sqrt(const Pack& x) {
#if defined(__AVX512F__)
#if defined(__GNUC__) && !defined(__clang__)  // (Clang has no such warning)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12's avx512fintrin.h: the masked form's unused source
#endif
  return Pack::raw(reinterpret_cast<Pack::V>(_mm512_sqrt_pd(reinterpret_cast<__m512d>(x.v))));
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#elif defined(__AVX2__)
  return Pack::raw(reinterpret_cast<Pack::V>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(x.v))));
#elif defined(__SSE2__)
  return Pack::raw(reinterpret_cast<Pack::V>(_mm_sqrt_pd(reinterpret_cast<__m128d>(x.v))));
#else
  Pack r;
  for (int k = 0; k < PACK_WIDTH; ++k) r.set(k, std::sqrt(x[k]));
  return r;
#endif
}

// The lanes where !(x > tol) (a pivot too small, or NaN), as a bit mask; for double 0 or 1. tol: one number for
// every lane, or a Pack of them.
inline int lanes_le(double x, double tol) { return !(x > tol) ? 1 : 0; }
inline int lanes_le(const Pack& x, double tol) {
  int mask = 0;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (!(x[k] > tol)) mask |= 1 << k;
  return mask;
}
inline int lanes_le(const Pack& x, const Pack& tol) {
  int mask = 0;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (!(x[k] > tol[k])) mask |= 1 << k;
  return mask;
}

// |x|, max(a, b) as std::fabs and std::max ((a < b) ? b : a) lane by lane.
inline double lane_abs(double x) { return std::fabs(x); }
inline Pack lane_abs(const Pack& x) {
  Pack r;
  for (int k = 0; k < PACK_WIDTH; ++k) r.set(k, std::fabs(x[k]));
  return r;
}
inline double lane_max(double a, double b) { return std::max(a, b); }
inline Pack lane_max(const Pack& a, const Pack& b) { return Pack::raw(a.v < b.v ? b.v : a.v); }

// The lanes where x ≤ y.
inline int lanes_at_most(double x, double y) { return x <= y ? 1 : 0; }
inline int lanes_at_most(const Pack& x, const Pack& y) {
  int mask = 0;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (x[k] <= y[k]) mask |= 1 << k;
  return mask;
}
template <class S>
constexpr int all_lanes() {
  return 1;
}
template <>
constexpr int all_lanes<Pack>() {
  return (1 << PACK_WIDTH) - 1;
}

// The lanes of `mask` from a, the others from b (double: mask ? a : b).
inline double blend(int mask, double a, double b) { return mask ? a : b; }
inline Pack blend(int mask, const Pack& a, const Pack& b) {
  Pack r = b;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (mask >> k & 1) r.set(k, a[k]);
  return r;
}

}  // namespace fdcore

// Counted: a double that counts the floating-point operations done on it (+, −, ×, ÷, √; one
// each), so that instantiating a kernel template for it gives the kernel's exact operation count
// for a model and a state (benchmarks: the fraction of the machine's arithmetic peak reached).
#pragma once

#include <cmath>
#include <cstdint>

#include "trig.hpp"

namespace fdcore {

struct Counted {
  double v = 0.0;
  static std::int64_t& ops() {
    thread_local std::int64_t n = 0;
    return n;
  }
  Counted() = default;
  Counted(double x) : v(x) {}  // NOLINT(google-explicit-constructor): scalars convert, as for double
  Counted& operator+=(const Counted& o) { ++ops(); v += o.v; return *this; }
  Counted& operator-=(const Counted& o) { ++ops(); v -= o.v; return *this; }
  Counted& operator*=(const Counted& o) { ++ops(); v *= o.v; return *this; }
};

inline Counted operator+(const Counted& a, const Counted& b) { ++Counted::ops(); return {a.v + b.v}; }
inline Counted operator-(const Counted& a, const Counted& b) { ++Counted::ops(); return {a.v - b.v}; }
inline Counted operator*(const Counted& a, const Counted& b) { ++Counted::ops(); return {a.v * b.v}; }
inline Counted operator/(const Counted& a, const Counted& b) { ++Counted::ops(); return {a.v / b.v}; }
inline Counted operator-(const Counted& a) { return {-a.v}; }  // a sign flip, not arithmetic
inline Counted sqrt(const Counted& a) { ++Counted::ops(); return {std::sqrt(a.v)}; }
// ABA's pivot test (a comparison, not counted)
inline int lanes_le(const Counted& x, double tol) { return !(x.v > tol) ? 1 : 0; }

// sin and cos: the operations of trig.hpp's reduction and polynomials (the quadrant's selection is not
// arithmetic), counted by running them on Counted.
inline void sin_cos(const Counted& x, Counted& s, Counted& c) {
  using namespace trig;
  const Counted n = (x * Counted(TWO_OVER_PI) + Counted(ROUND)) - Counted(ROUND);
  const Counted r = ((x - n * Counted(P1)) - n * Counted(P2)) - n * Counted(P3);
  Counted sr, cr;
  kernel(r, sr, cr);
  double sd, cd;
  sin_cos(x.v, sd, cd);
  s = sd;
  c = cd;
}

}  // namespace fdcore

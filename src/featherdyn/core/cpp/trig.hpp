// sin and cos of a joint angle, written once for double and for the SIMD Pack, so that a batched
// lane runs exactly the IEEE operations of the one-state kernel (bit-identical lanes) while four
// angles cost one polynomial evaluation instead of eight scalar library calls.
//
//   x = n·π/2 + r,  n = round(x · 2/π),  |r| ≤ π/4   (Cody & Waite's reduction, π/2 in three parts
//                                                      P1 + P2 + P3, P1 and P2 with 33 significant
//                                                      bits so that n·P1 and n·P2 are exact)
//   sin r = r + r³ (S1 + r² S2 + … + r¹⁰ S6),   cos r = 1 − r²/2 + r⁴ (C1 + r² C2 + … + r¹⁰ C6)
//   (sin x, cos x) = (sin r, cos r), (cos r, −sin r), (−sin r, −cos r), (−cos r, sin r) for n mod 4
//
// The polynomials are the minimax approximations on [−π/4, π/4] published with Sun's fdlibm
// (k_sin.c, k_cos.c; error below one unit in the last place). |x| > REDUCE_MAX, where the
// three-part reduction would lose digits, and non-finite x go to the C library lane by lane
// (the same rule for double and Pack). std::complex keeps std::sin / std::cos (complex step).
#pragma once

#include <cmath>
#include <complex>
#include <cstdint>

#include "pack.hpp"

namespace fdcore {

namespace trig {
constexpr double TWO_OVER_PI = 6.36619772367581382433e-01;
constexpr double P1 = 1.57079632673412561417e+00;   // π/2, first 33 bits
constexpr double P2 = 6.07710050630396597660e-11;   // the next 33 bits
constexpr double P3 = 2.02226624879595063154e-21;   // the rest
constexpr double ROUND = 6755399441055744.0;        // 1.5 · 2⁵²: (y + ROUND) − ROUND rounds y to an integer
constexpr double REDUCE_MAX = 1.0e5;
constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                 S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                 S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                 C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                 C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;

// (sin r, cos r) for |r| ≤ π/4; cos as w + ((1 − w) − r²/2 + …) with w = 1 − r²/2 (keeps the last bit)
// (the polynomials by Estrin's scheme: pairs of terms in parallel, then powers of z² — a shorter chain of
// dependent operations than Horner's, on the one-state path where latency, not throughput, counts)
template <class S>
inline void kernel(const S& r, S& s, S& c) {
  const S z = r * r;
  const S z2 = z * z;
  const S ps = (S(S2) + z * S(S3)) + z2 * ((S(S4) + z * S(S5)) + z2 * S(S6));
  s = r + r * z * (S(S1) + z * ps);
  const S pc = z * ((S(C1) + z * S(C2)) + z2 * ((S(C3) + z * S(C4)) + z2 * (S(C5) + z * S(C6))));
  const S hz = S(0.5) * z;
  const S w = S(1.0) - hz;
  c = w + (((S(1.0) - w) - hz) + z * pc);
}
}  // namespace trig

#if defined(__GNUC__) || defined(__clang__)
__attribute__((always_inline))
#endif
inline void sin_cos(double x, double& s, double& c) {
  using namespace trig;
  if (!(std::fabs(x) <= REDUCE_MAX)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  const double n = (x * TWO_OVER_PI + ROUND) - ROUND;
  const double r = ((x - n * P1) - n * P2) - n * P3;
  double sr, cr;
  kernel(r, sr, cr);
  const int q = static_cast<int>(static_cast<std::int64_t>(n) & 3);
  s = q == 0 ? sr : q == 1 ? cr : q == 2 ? -sr : -cr;
  c = q == 0 ? cr : q == 1 ? -sr : q == 2 ? -cr : sr;
}

inline void sin_cos(const Pack& x, Pack& s, Pack& c) {
  using namespace trig;
  typedef long long I __attribute__((vector_size(8 * PACK_WIDTH)));
  Pack ax;
  bool wide = false;
  for (int k = 0; k < PACK_WIDTH; ++k) {
    ax.set(k, std::fabs(x[k]));
    wide = wide || !(ax[k] <= REDUCE_MAX);
  }
  if (wide) {  // some lane out of the reduction's range: every lane by the one-state rule
    for (int k = 0; k < PACK_WIDTH; ++k) {
      double sk, ck;
      sin_cos(x[k], sk, ck);
      s.set(k, sk);
      c.set(k, ck);
    }
    return;
  }
  const Pack n = (x * Pack(TWO_OVER_PI) + Pack(ROUND)) - Pack(ROUND);
  const Pack r = ((x - n * Pack(P1)) - n * Pack(P2)) - n * Pack(P3);
  Pack sr, cr;
  kernel(r, sr, cr);
  const I q = __builtin_convertvector(n.v, I) & 3;
  const I swap = (q & 1) != 0;          // quadrants 1, 3: sin ↔ cos
  const I neg_s = (q == 2) | (q == 3);  // sin x < 0 part
  const I neg_c = (q == 1) | (q == 2);
  const Pack::V a = swap ? cr.v : sr.v, b = swap ? sr.v : cr.v;
  s.v = neg_s ? -a : a;
  c.v = neg_c ? -b : b;
}

inline void sin_cos(const std::complex<double>& x, std::complex<double>& s, std::complex<double>& c) {
  s = std::sin(x);
  c = std::cos(x);
}

}  // namespace fdcore

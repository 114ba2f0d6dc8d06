// Which of the instruction sets the batched kernels are also compiled for (simd_avx2.cpp, simd_avx512.cpp) this
// CPU *and* its operating system can run: CPUID's feature bits, and XGETBV's register-state word XCR0 (a wide
// register the operating system does not save on a context switch cannot be used, whatever CPUID says).
// The same code under GCC, Clang, Apple Clang and clang-cl: __builtin_cpu_supports needs the compiler's runtime
// library (__cpu_model), which clang-cl does not link by default. (macOS turns the AVX-512 state on lazily, so
// XCR0 may not show it there: such a Mac runs the AVX2 kernels, which is slower but never wrong.)
#pragma once

#include <cstdint>

#if defined(__x86_64__) || defined(_M_X64)
#define FEATHERDYN_X86_64 1
#if defined(_MSC_VER)
#include <intrin.h>
#else
#include <cpuid.h>
#endif
#endif

namespace fdcore {
namespace cpu {

#if defined(FEATHERDYN_X86_64)
// CPUID of (leaf, subleaf) into r = {eax, ebx, ecx, edx}.
inline void cpuid(unsigned leaf, unsigned subleaf, unsigned r[4]) {
#if defined(_MSC_VER)
  int x[4];
  __cpuidex(x, static_cast<int>(leaf), static_cast<int>(subleaf));
  for (int k = 0; k < 4; ++k) r[k] = static_cast<unsigned>(x[k]);
#else
  __cpuid_count(leaf, subleaf, r[0], r[1], r[2], r[3]);
#endif
}

// XCR0, the register state the operating system saves (read only when CPUID says OSXSAVE).
inline std::uint64_t xcr0() {
#if defined(_MSC_VER) && !defined(__clang__)
  return _xgetbv(0);
#else  // (Clang's _xgetbv wants the function compiled for XSAVE: the instruction itself instead)
  unsigned lo = 0, hi = 0;
  __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
#endif
}

struct Features {
  bool avx2 = false, avx512f = false;
};

inline Features detect() {
  Features f;
  unsigned r[4];
  cpuid(0, 0, r);
  const unsigned max_leaf = r[0];
  if (max_leaf < 7) return f;
  cpuid(1, 0, r);
  const bool osxsave = (r[2] >> 27) & 1u, avx = (r[2] >> 28) & 1u;
  if (!osxsave || !avx) return f;
  const std::uint64_t xcr = xcr0();
  const bool ymm = (xcr & 0x6u) == 0x6u;     // SSE and AVX state
  const bool zmm = (xcr & 0xE6u) == 0xE6u;   // and the opmask and both halves of the 512-bit registers
  cpuid(7, 0, r);
  f.avx2 = ymm && ((r[1] >> 5) & 1u);
  f.avx512f = zmm && ((r[1] >> 16) & 1u);
  return f;
}
#else
struct Features {
  bool avx2 = false, avx512f = false;
};
inline Features detect() { return Features{}; }
#endif

// This CPU's features, detected once.
inline const Features& features() {
  static const Features f = detect();
  return f;
}

}  // namespace cpu
}  // namespace fdcore

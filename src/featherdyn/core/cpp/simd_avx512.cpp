// The batched kernels compiled for AVX-512 (this file alone gets -mavx512f; no -mfma, and the core's
// -ffp-contract=off, so every lane still rounds like the one-state kernel). Everything from the
// kernel headers lands in namespace fdcore_avx512, so these instantiations never mix with the
// baseline ones; bindings.cpp calls them only when the CPU has AVX-512F.
#include "checks.hpp"
#include "groups.hpp"
#include "model_view.hpp"

namespace fdbase = fdcore;
#define fdcore fdcore_avx512
#include "simd_kernels.inc"

fdgroup::GroupKernels featherdyn_avx512_group_kernels() { return fdcore::group_kernels("avx512"); }

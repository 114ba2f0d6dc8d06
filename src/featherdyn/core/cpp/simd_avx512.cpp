// The batched kernels compiled for AVX-512 (this file alone gets -mavx512f; no -mfma, and the core's
// -ffp-contract=off, so every lane still rounds like the one-state kernel). Everything from the
// kernel headers lands in namespace fdcore_avx512, so these instantiations never mix with the
// baseline ones; bindings.cpp calls them only when the CPU has AVX-512F.
#include "checks.hpp"
#include "groups.hpp"
#include "model_view.hpp"

namespace fdbase = fdcore;
#define fdcore fdcore_avx512
namespace fdcore {
using fdbase::ModelView;
using fdbase::REVOLUTE;
using fdbase::PRISMATIC;
using fdbase::SPHERICAL;
using fdbase::FREE_FLYER;
using fdbase::PLANAR;
using fdbase::ContactSpec;  // contacts.hpp: the checks' status codes and the specs come from the baseline headers
using fdbase::make_status;
using fdbase::OK;
using fdbase::SINGULAR;
using fdbase::LENGTH;
using fdbase::ARG_Q;
using fdbase::ARG_OUT;
}  // namespace fdcore
#include "simd_groups.hpp"

fdgroup::GroupKernels featherdyn_avx512_group_kernels() { return fdcore::group_kernels("avx512"); }

// The declared algorithms (declare.hpp): each a name, its operands with symbolic shapes and its kernel on one
// state; `declared_kernels` lists them for the binding. Adding an algorithm here, its reference in
// featherdyn/algorithms/ and its declaration in featherdyn/api/declarations.py makes its public function,
// out=, batch, Dask and fd.compile forms (docs/architecture.md, "Adding an algorithm").
#pragma once

#include <vector>

#include "declare.hpp"
#include "derivatives.hpp"

namespace fdcore {

// ∂g/∂q (nv, nv): the generalized gravity g(q) = RNEA(q, 0, 0) differentiated along q's tangent — the
// analytical RNEA derivatives (derivatives.hpp) at rest, q̇ = q̈ = 0: no q̇ given, the velocity terms not formed
// (Pinocchio's computeGeneralizedGravityDerivatives).
struct GeneralizedGravityDerivatives {
  static constexpr const char* name = "generalized_gravity_derivatives";
  static constexpr Operand inputs[] = {{"q", ARG_Q, {NQ}, 1, false}};
  static constexpr Operand outputs[] = {{"dg_dq", ARG_OUT, {NV, NV}, 2, false}};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out) {
    group_kernels().rnea_derivatives(mv, in[0], nullptr, nullptr, nullptr, true, out[0], nullptr, nullptr);  // at rest
    return OK;
  }
};

// ∂τ_s/∂q (nv, nv) of the static torque τ_s(q) = g(q) − Σ_i J_iᵀ f_i = RNEA(q, 0, 0, f_ext), the body-frame
// forces f_ext (nb, 6) held fixed in their bodies (Pinocchio's computeStaticTorqueDerivatives).
struct StaticTorqueDerivatives {
  static constexpr const char* name = "static_torque_derivatives";
  static constexpr Operand inputs[] = {{"q", ARG_Q, {NQ}, 1, false}, {"f_ext", ARG_FEXT, {NB, 6}, 2, false}};
  static constexpr Operand outputs[] = {{"dtau_dq", ARG_OUT, {NV, NV}, 2, false}};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out) {
    group_kernels().rnea_derivatives(mv, in[0], nullptr, nullptr, in[1], true, out[0], nullptr, nullptr);  // at rest
    return OK;
  }
};

// Every declared algorithm, made once (their addresses are kept by the binding's public calls).
inline const std::vector<Kernel>& declared_kernels() {
  static const std::vector<Kernel> kernels = {declare<GeneralizedGravityDerivatives>(), declare<StaticTorqueDerivatives>()};
  return kernels;
}

}  // namespace fdcore

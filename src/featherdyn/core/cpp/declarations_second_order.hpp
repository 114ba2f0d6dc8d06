// The declarations (declare.hpp) of the second-order derivatives (second_order.hpp): listed in
// declarations.hpp's make_declared_kernels().
#pragma once

#include "declarations_constraints.hpp"  // (singular_at_rest)
#include "declare.hpp"
#include "second_order.hpp"

namespace fdcore {

namespace operand {
constexpr Operand tensor(const char* name) { return {name, ARG_OUT, {NV, NV, NV}, 3, false}; }  // (nv, nv, nv)
}  // namespace operand

// (∂²τ/∂q², ∂²τ/∂q̇², ∂²τ/∂q∂q̇, ∂M/∂q) (nv, nv, nv) of τ = RNEA(q, q̇, q̈, f_ext), [i, j, k] = ∂²τ_i/∂x_j∂y_k and
// ∂M_ij/∂q_k: the analytical recursion of Singh, Russell & Wensing (rnea_second_order.hpp).
struct RneaSecondDerivatives : Declared {
  static constexpr const char* name = "rnea_second_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a, operand::f_ext};
  static constexpr Operand outputs[] = {operand::tensor("d2tau_dq2"), operand::tensor("d2tau_dv2"),
                                        operand::tensor("d2tau_dqdv"), operand::tensor("dM_dq")};
  static constexpr unsigned options = GRAVITY;
  static constexpr bool checks_outputs = true;  // the kernel bounds its factors; beyond them, the outputs are scanned
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    const bool bounded = group_kernels().rnea_second_derivatives(mv, in[0], in[1], in[2], in[3], opt.gravity,
                                                                 out[0], out[1], out[2], out[3]);
    return bounded ? OK : declared::finite_outputs(mv, opt, outputs, std::size(outputs), out);
  }
};

// (∂²q̈/∂q², ∂²q̈/∂q̇², ∂²q̈/∂q∂q̇, ∂²q̈/∂q∂τ) (nv, nv, nv) of q̈ = ABA(q, q̇, τ, f_ext), from the inverse-dynamics
// ones (second_order.hpp). Status SINGULAR naming the joint, when M(q) is singular.
struct AbaSecondDerivatives : Declared {
  static constexpr const char* name = "aba_second_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::tau, operand::f_ext};
  static constexpr Operand outputs[] = {operand::tensor("d2ddq_dq2"), operand::tensor("d2ddq_dv2"),
                                        operand::tensor("d2ddq_dqdv"), operand::tensor("d2ddq_dqdtau")};
  static constexpr unsigned options = GRAVITY;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    const int bad = group_kernels().aba_second_derivatives(mv, in[0], in[1], in[2], in[3], opt.gravity, out[0],
                                                           out[1], out[2], out[3]);
    return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
  }
};

}  // namespace fdcore

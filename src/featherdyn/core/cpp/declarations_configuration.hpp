// The declarations (declare.hpp) of the configuration space's maps (configuration.hpp): listed in
// declarations.hpp's make_declared_kernels(). difference takes two configurations: q0 checked as q is (ARG_Q), q1 as the
// second configuration (ARG_Q1: length nq, finite, unit quaternions).
#pragma once

#include <vector>

#include "configuration.hpp"
#include "declare.hpp"

namespace fdcore {

// q' (nq,) = q ⊕ v: the configuration reached from q moving with v for unit time (configuration.hpp).
struct Integrate : Declared {
  static constexpr const char* name = "integrate";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::vector("q_next", NQ)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    integrate(mv, in[0], in[1], out[0]);
    return OK;
  }
};

// v (nv,) = q1 ⊖ q0, with integrate(q0, v) = q1 (rotations the shorter way).
struct Difference : Declared {
  static constexpr const char* name = "difference";
  static constexpr Operand inputs[] = {operand::q0, operand::q1};
  static constexpr Operand outputs[] = {operand::vector("v", NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    difference(mv, in[0], in[1], out[0]);
    return OK;
  }
};

// (J_q, J_v) (nv, nv), block-diagonal: J_q = Ad(exp(v))⁻¹, J_v = Jr(v) per joint.
struct IntegrateDerivatives : Declared {
  static constexpr const char* name = "integrate_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::matrix("J_q", NV, NV), operand::matrix("J_v", NV, NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    integrate_derivatives(mv, in[1], out[0], out[1]);
    return OK;
  }
};

// (J_0, J_1) (nv, nv), block-diagonal: J_1 = Jr(v)⁻¹, J_0 = −Jr(v)⁻¹ Ad(exp(v))⁻¹ per joint, v = difference(q0, q1).
struct DifferenceDerivatives : Declared {
  static constexpr const char* name = "difference_derivatives";
  static constexpr Operand inputs[] = {operand::q0, operand::q1};
  static constexpr Operand outputs[] = {operand::matrix("J_0", NV, NV), operand::matrix("J_1", NV, NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    thread_local std::vector<double> v;
    v.resize(static_cast<size_t>(mv.nv));
    difference(mv, in[0], in[1], v.data());
    difference_derivatives(mv, v.data(), out[0], out[1]);
    return OK;
  }
};

}  // namespace fdcore

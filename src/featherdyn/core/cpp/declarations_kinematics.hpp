// The declared motions of frames and the derivatives of kinematic quantities (declare.hpp; listed in
// declarations.hpp's make_declared_kernels()): a frame's velocity and accelerations (frames.hpp), and their derivatives,
// the centre of mass's, the centroidal momentum's and its rate's against the state (kinematics_derivatives.hpp).
// Their public declarations: featherdyn/api/declarations.py.
#pragma once

#include "declare.hpp"
#include "frames.hpp"
#include "kinematics_derivatives.hpp"

namespace fdcore {

// A frame's spatial velocity (6,) rows [ω; v] in `reference` (frames.hpp: frame_motion; Pinocchio's
// getFrameVelocity): LOCAL ᶠX_b v_b, WORLD ⁰X_f ᶠv, LOCAL_WORLD_ALIGNED [⁰R_f ω; ⁰R_f v].
struct FrameVelocity : Declared {
  static constexpr const char* name = "frame_velocity";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::vector("motion", 6)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    frame_motion<double>(mv, in[0], in[1], nullptr, opt.frame, opt.reference, out[0], nullptr, nullptr);
    return OK;
  }
};

// A frame's spatial acceleration (6,) (no gravity), expressed as its velocity (getFrameAcceleration).
struct FrameAcceleration : Declared {
  static constexpr const char* name = "frame_acceleration";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a};
  static constexpr Operand outputs[] = {operand::vector("motion", 6)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    frame_motion<double>(mv, in[0], in[1], in[2], opt.frame, opt.reference, nullptr, out[0], nullptr);
    return OK;
  }
};

// A frame's classical acceleration (6,) [ω̇; a_lin + ω × v_lin] (getFrameClassicalAcceleration): in LOCAL and
// LOCAL_WORLD_ALIGNED the acceleration of the frame's origin, in WORLD of the body point at the world origin.
struct FrameClassicalAcceleration : Declared {
  static constexpr const char* name = "frame_classical_acceleration";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a};
  static constexpr Operand outputs[] = {operand::vector("motion", 6)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    frame_motion<double>(mv, in[0], in[1], in[2], opt.frame, opt.reference, nullptr, nullptr, out[0]);
    return OK;
  }
};

// The derivatives of a frame's velocity v, spatial acceleration a and classical acceleration
// a^c = [ω̇; a_lin + ω × v_lin] in a reference, each (6, nv), in the order of fd.KinematicsDerivatives' fields:
// (∂v/∂q, ∂v/∂q̇, ∂a/∂q, ∂a/∂q̇, ∂a/∂q̈, ∂a^c/∂q, ∂a^c/∂q̇, ∂a^c/∂q̈), where ∂a/∂q̈ = ∂a^c/∂q̈ = ∂v/∂q̇ = J (copies).
inline constexpr Operand kinematics_derivatives_outputs[] = {
    operand::matrix("dv_dq", 6, NV),  operand::matrix("dv_dv", 6, NV),  operand::matrix("da_dq", 6, NV),
    operand::matrix("da_dv", 6, NV),  operand::matrix("da_da", 6, NV),  operand::matrix("dac_dq", 6, NV),
    operand::matrix("dac_dv", 6, NV), operand::matrix("dac_da", 6, NV)};

struct KinematicsDerivatives : Declared {
  static constexpr const char* name = "kinematics_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a, operand::point};
  static constexpr const auto& outputs = kinematics_derivatives_outputs;
  static constexpr unsigned options = FRAME | REFERENCE;
  static constexpr auto group = &fdgroup::GroupKernels::kinematics_derivatives;  // (rows without a point)
  // kinematics_derivatives.hpp's six outputs (∂v/∂q, J, ∂a/∂q, ∂a/∂q̇, ∂a^c/∂q, ∂a^c/∂q̇) among the eight, then J
  // into ∂a/∂q̈ and ∂a^c/∂q̈; with a point in[3] (3) in the frame's coordinates, those of the frame moved to that
  // point with its orientation kept (Pinocchio's getPoint*Derivatives in the linear rows), else at its origin
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    double* const six[6] = {out[0], out[1], out[2], out[3], out[5], out[6]};
    kinematics_derivatives(mv, in[0], in[1], in[2], opt.frame, in[3], opt.reference, six);
    const size_t n = static_cast<size_t>(6) * mv.nv;
    std::copy_n(out[1], n, out[4]);
    std::copy_n(out[1], n, out[7]);
    return OK;
  }
};

// (∂c/∂q, ∂ċ/∂q) (3, nv) of the centre of mass c and its velocity ċ in world coordinates (∂ċ/∂q̇ = ∂c/∂q).
struct CenterOfMassDerivatives : Declared {
  static constexpr const char* name = "center_of_mass_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::matrix("dc_dq", 3, NV), operand::matrix("dcdot_dq", 3, NV)};
  static constexpr auto group = &fdgroup::GroupKernels::center_of_mass_derivatives;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    const double mass = total_mass(mv);
    if (mass == 0.0) return make_status(NO_MASS, ARG_Q, 0);
    center_of_mass_derivatives(mv, in[0], in[1], mass, out[0], out[1]);
    return OK;
  }
};

// (∂h_G/∂q, ∂ḣ_G/∂q, ∂ḣ_G/∂q̇, ∂ḣ_G/∂q̈) (6, nv) of the centroidal momentum h_G = [k_G; p] and its rate
// (∂h_G/∂q̇ = ∂ḣ_G/∂q̈ = A_G).
struct CentroidalDynamicsDerivatives : Declared {
  static constexpr const char* name = "centroidal_dynamics_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a};
  static constexpr Operand outputs[] = {operand::matrix("dh_dq", 6, NV), operand::matrix("dhdot_dq", 6, NV),
                                        operand::matrix("dhdot_dv", 6, NV), operand::matrix("dhdot_da", 6, NV)};
  static constexpr auto group = &fdgroup::GroupKernels::centroidal_dynamics_derivatives;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    const double mass = total_mass(mv);
    if (mass == 0.0) return make_status(NO_MASS, ARG_Q, 0);
    centroidal_dynamics_derivatives(mv, in[0], in[1], in[2], mass, out);
    return OK;
  }
};

}  // namespace fdcore

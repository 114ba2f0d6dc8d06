// Input checks done inside the core, returning a status the Python side turns into the
// reference's exception and message (featherdyn/core/_errors.py):
//
//     status = code | arg << 3 | index << 8
//
// code: OK, LENGTH (index = the wrong length), NONFINITE (index = the first bad element),
// QUATERNION (index = the body whose quaternion is off unit norm), SINGULAR (index = the joint), OVERLAP (an
// output shares memory with the input `arg`, or with another output: arg = ARG_OUT), NO_MASS (a massless tree),
// CONSTRAINT (index = m: constraint rows whose J M⁻¹ Jᵀ is singular, where no solver setting can go on);
// arg: which input (ARG_Q, ARG_V, ARG_A (a or τ), ARG_FEXT, ARG_OUT, ARG_FRAME, ARG_J and ARG_C: constraint rows
// J q̈ = c, which are not part of the state check; ARG_Q1: a second configuration, fd.difference's q1, checked as q
// is — its first, q0, takes ARG_Q; ARG_W: a cotangent, w (nv) of fd.rnea_vjp or W (nv, nv) of fd.crba_vjp, checked finite after the state;
// ARG_POINT: a point (3) in a frame's coordinates, fd.kinematics_derivatives' point, checked finite after the state).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "model_view.hpp"

namespace fdcore {

enum StatusCode : std::int64_t { OK = 0, LENGTH = 1, NONFINITE = 2, QUATERNION = 3, SINGULAR = 4, OVERLAP = 5,
                                 NO_MASS = 6, CONSTRAINT = 7 };
enum Arg : std::int64_t { ARG_Q = 0, ARG_V = 1, ARG_A = 2, ARG_FEXT = 3, ARG_OUT = 4, ARG_FRAME = 5, ARG_J = 6,
                          ARG_C = 7, ARG_Q1 = 8, ARG_W = 9, ARG_POINT = 10 };
// The names of the status arguments, for a status worded in C++ (the XLA FFI handler's errors).
constexpr const char* ARG_WORDS[] = {"q", "v", "a or tau", "f_ext", "out", "frame", "J", "c", "q1", "w", "point"};

// (an unknown index, e.g. the length of an array that is not 1-D, is given as −1 and stored as 0)
inline std::int64_t make_status(std::int64_t code, std::int64_t arg, std::int64_t index) {
  return code | (arg << 3) | ((index < 0 ? 0 : index) << 8);
}

#include "finite_scan.inc"  // all_finite(x, n)

// The index of the first non-finite x[k], or −1 (an early-exit scan: only to name a failure all_finite found).
inline std::int64_t first_nonfinite(const double* x, std::int64_t n) {
  for (std::int64_t k = 0; k < n; ++k)
    if (!std::isfinite(x[k])) return k;
  return -1;
}

// The first body whose joint quaternion (spherical q_i, free-flyer q_i[3:7]) is off unit norm by more
// than mv.quat_tol (featherdyn.tolerances.QUATERNION_NORM for float64), or −1.
inline int first_bad_quaternion(const ModelView& mv, const double* q) {
  for (int k = 0; k < mv.nquat; ++k) {
    const double* quat = q + mv.quat_q[k];
    const double norm = std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
    if (!(std::fabs(norm - 1.0) <= mv.quat_tol)) return mv.quat_body[k];
  }
  return -1;
}

// Finiteness of q and of each vector (nullptr skipped), then unit quaternions: OK or the first failure.
// all_finite's scans first (the early-exit scans that name a failure do not vectorise: 40 ns of a talos
// call, 4 % of a talos batch row on packs).
inline std::int64_t check_state(const ModelView& mv, const double* q, const double* v, const double* a,
                                const double* f_ext) {
  if (all_finite(q, mv.nq) && (!v || all_finite(v, mv.nv)) && (!a || all_finite(a, mv.nv)) &&
      (!f_ext || all_finite(f_ext, 6 * static_cast<std::int64_t>(mv.nb))) && first_bad_quaternion(mv, q) < 0)
    return OK;
  std::int64_t k = first_nonfinite(q, mv.nq);
  if (k >= 0) return make_status(NONFINITE, ARG_Q, k);
  if (v && (k = first_nonfinite(v, mv.nv)) >= 0) return make_status(NONFINITE, ARG_V, k);
  if (a && (k = first_nonfinite(a, mv.nv)) >= 0) return make_status(NONFINITE, ARG_A, k);
  if (f_ext && (k = first_nonfinite(f_ext, 6 * static_cast<std::int64_t>(mv.nb))) >= 0)
    return make_status(NONFINITE, ARG_FEXT, k);
  const int i = first_bad_quaternion(mv, q);
  if (i >= 0) return make_status(QUATERNION, ARG_Q, i);
  return OK;
}

// A configuration besides q (status argument `arg`: ARG_Q1), checked as q is: finite, then unit quaternions.
inline std::int64_t check_configuration(const ModelView& mv, const double* q, std::int64_t arg) {
  if (all_finite(q, mv.nq) && first_bad_quaternion(mv, q) < 0) return OK;
  const std::int64_t k = first_nonfinite(q, mv.nq);
  if (k >= 0) return make_status(NONFINITE, arg, k);
  return make_status(QUATERNION, arg, first_bad_quaternion(mv, q));
}

}  // namespace fdcore

// Input checks done inside the core, returning a status the Python side turns into the
// reference's exception and message (featherdyn/core/_errors.py):
//
//     status = code | arg << 3 | index << 8
//
// code: OK, LENGTH (index = the wrong length), NONFINITE (index = the first bad element),
// QUATERNION (index = the body whose quaternion is off unit norm), SINGULAR (index = the joint);
// arg: which input (ARG_Q, ARG_V, ARG_A (a or τ), ARG_FEXT, ARG_OUT, ARG_FRAME).
#pragma once

#include <cmath>
#include <cstdint>

#include "model_view.hpp"

namespace fdcore {

enum StatusCode : std::int64_t { OK = 0, LENGTH = 1, NONFINITE = 2, QUATERNION = 3, SINGULAR = 4 };
enum Arg : std::int64_t { ARG_Q = 0, ARG_V = 1, ARG_A = 2, ARG_FEXT = 3, ARG_OUT = 4, ARG_FRAME = 5 };

// (an unknown index, e.g. the length of an array that is not 1-D, is given as −1 and stored as 0)
inline std::int64_t make_status(std::int64_t code, std::int64_t arg, std::int64_t index) {
  return code | (arg << 3) | ((index < 0 ? 0 : index) << 8);
}

// The index of the first non-finite x[k], or −1.
inline std::int64_t first_nonfinite(const double* x, std::int64_t n) {
  for (std::int64_t k = 0; k < n; ++k)
    if (!std::isfinite(x[k])) return k;
  return -1;
}

// The first body whose joint quaternion (spherical q_i, free-flyer q_i[3:7]) is off unit norm by more
// than mv.quat_tol (featherdyn.tolerances.QUATERNION_NORM for float64), or −1.
inline int first_bad_quaternion(const ModelView& mv, const double* q) {
  for (int i = 0; i < mv.nb; ++i) {
    const double* quat;
    if (mv.jtype[i] == SPHERICAL)
      quat = q + mv.idx_q[i];
    else if (mv.jtype[i] == FREE_FLYER)
      quat = q + mv.idx_q[i] + 3;
    else
      continue;
    const double norm = std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
    if (!(std::fabs(norm - 1.0) <= mv.quat_tol)) return i;
  }
  return -1;
}

// Finiteness of q and of each vector (nullptr skipped), then unit quaternions: OK or the first failure.
inline std::int64_t check_state(const ModelView& mv, const double* q, const double* v, const double* a,
                                const double* f_ext) {
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

}  // namespace fdcore

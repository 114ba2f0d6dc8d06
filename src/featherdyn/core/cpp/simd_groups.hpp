// The batched kernels of one group of PACK_WIDTH rows: gather the rows into Packs, run the same
// templates as one state (instantiated for Pack), scatter the result. Included by bindings.cpp
// (the x86-64 baseline) and by simd_avx2.cpp (compiled with -mavx2 in its own namespace).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "aba.hpp"
#include "checks.hpp"
#include "contact_derivatives.hpp"
#include "contacts.hpp"
#include "crba.hpp"
#include "derivatives.hpp"
#include "energy.hpp"
#include "kinematics_derivatives.hpp"
#include "vjp.hpp"
#include "groups.hpp"
#include "kinematics.hpp"
#include "pack.hpp"
#include "rnea.hpp"
#include "second_order.hpp"

namespace fdcore {

// W rows of the inputs gathered into Packs, and results scattered back; one buffer per thread,
// sized before any pointer is handed out.
struct Lanes {
  std::vector<Pack> buf;
  Pack* gather(const fdgroup::Rows& X, std::int64_t r0, size_t n, size_t offset) {
    if (!X.p) return nullptr;
    Pack* out = buf.data() + offset;
    const double* rows[PACK_WIDTH];
    for (int lane = 0; lane < PACK_WIDTH; ++lane) rows[lane] = X.row(r0 + lane);
    for (size_t k = 0; k < n; ++k) out[k] = load_lanes(rows, k);
    return out;
  }
  Pack* space(size_t offset) { return buf.data() + offset; }
};

// In blocks of W entries: the block's W Packs transposed in registers (pack.hpp: transpose_lanes), then each
// lane's W consecutive entries written as one Pack (2026-12-01: the scalar copy it replaces was 18 % of panda's
// kinematics-derivatives batch).
inline void scatter(const Pack* x, size_t n, double* out, std::int64_t stride) {
  size_t k0 = 0;
  for (; k0 + PACK_WIDTH <= n; k0 += PACK_WIDTH) {
    Pack r[PACK_WIDTH];
    for (int j = 0; j < PACK_WIDTH; ++j) r[j] = x[k0 + j];
    transpose_lanes(r);
    for (int lane = 0; lane < PACK_WIDTH; ++lane) std::memcpy(out + lane * stride + k0, &r[lane].v, sizeof(Pack::V));
  }
  for (int lane = 0; lane < PACK_WIDTH; ++lane)
    for (size_t k = k0; k < n; ++k) out[lane * stride + k] = x[k][lane];
}

// The same for a result too large for the caches: each lane's row written in whole 64-byte lines with
// non-temporal stores (no read of the line first: half the memory traffic), the partial lines at both ends
// with ordinary stores; the fence orders the stores before the pool reports the chunk done.
inline void scatter_lines(const Pack* x, size_t n, double* out, std::int64_t stride) {
#if defined(__SSE2__)
  size_t head[PACK_WIDTH];  // entries before the lane's first whole line
  for (int lane = 0; lane < PACK_WIDTH; ++lane) {
    const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(out + lane * stride);
    head[lane] = std::min(n, static_cast<size_t>((8 - (at / 8) % 8) % 8));
    for (size_t k = 0; k < head[lane]; ++k) out[lane * stride + k] = x[k][lane];
  }
  for (size_t k0 = 0;; k0 += 8) {
    bool any = false;
    for (int lane = 0; lane < PACK_WIDTH; ++lane) {
      const size_t s = head[lane] + k0;
      if (s + 8 > n) continue;
      any = true;
      double* o = out + lane * stride + s;
      for (int j = 0; j < 8; j += 2) _mm_stream_pd(o + j, _mm_set_pd(x[s + j + 1][lane], x[s + j][lane]));
    }
    if (!any) break;
  }
  for (int lane = 0; lane < PACK_WIDTH; ++lane)
    for (size_t k = head[lane] + (n - head[lane]) / 8 * 8; k < n; ++k) out[lane * stride + k] = x[k][lane];
  _mm_sfence();
#else
  scatter(x, n, out, stride);
#endif
}

inline Lanes& thread_lanes(size_t total) {
  thread_local Lanes lanes;
  if (lanes.buf.size() < total) lanes.buf.resize(total);
  return lanes;
}

// A group's state, gathered into the thread's Lanes from its start: q, q̇, q̈ or τ (g.A) and f_ext (nullptr where a row
// has none), then `extra` Packs of room (`rest`).
struct GroupState {
  const Pack *q, *v, *a, *f;
  Pack* rest;
};
inline GroupState gather_state(const fdgroup::GroupArgs& g, std::int64_t r0, size_t extra) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv, nf = 6 * static_cast<size_t>(mv.nb);
  Lanes& L = thread_lanes(nq + 2 * nv + nf + extra);
  return {L.gather(g.Q, r0, nq, 0), L.gather(g.V, r0, nv, nq), L.gather(g.A, r0, nv, nq + nv),
          L.gather(g.FX, r0, nf, nq + 2 * nv), L.space(nq + 2 * nv + nf)};
}

// The first n outputs of a group (Packs x[o], len[o] numbers a row) into g.outs[o]'s rows r0 …, each row as long as its
// output's shape.
inline void scatter_outputs(const fdgroup::GroupArgs& g, std::int64_t r0, const Pack* const* x, const size_t* len,
                            int n) {
  for (int o = 0; o < n; ++o) {
    const std::int64_t l = static_cast<std::int64_t>(len[o]);
    scatter(x[o], len[o], g.outs[o] + r0 * l, l);
  }
}

inline std::int64_t rnea_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nv = mv.nv;
  const GroupState st = gather_state(g, r0, nv);
  Pack* tau = st.rest;
  rnea(mv, st.q, st.v, st.a, st.f, g.gravity, tau);
  if (!all_finite(tau, nv)) return 1;  // finite input overflowed in some lane: redone row by row, which says where
  scatter(tau, nv, g.outs[0] + r0 * g.out_stride, g.out_stride);
  return 0;
}

inline std::int64_t crba_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv2 = static_cast<size_t>(mv.nv) * mv.nv;
  Lanes& L = thread_lanes(nq + nv2);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  Pack* M = L.space(nq);
  crba(mv, q, M);
  if (!all_finite(M, nv2)) return 1;
  (g.stream ? scatter_lines : scatter)(M, nv2, g.outs[0] + r0 * g.out_stride, g.out_stride);
  return 0;
}

inline std::int64_t aba_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nv = mv.nv;
  const GroupState st = gather_state(g, r0, nv);
  Pack* qdd = st.rest;
  if (aba(mv, st.q, st.v, st.a, st.f, g.gravity, qdd) >= 0 || !all_finite(qdd, nv)) return 1;  // singular or overflowed
  scatter(qdd, nv, g.outs[0] + r0 * g.out_stride, g.out_stride);
  return 0;
}

inline std::int64_t fk_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, n = 16 * static_cast<size_t>(mv.nb);
  Lanes& L = thread_lanes(nq + n);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  Pack* H = L.space(nq);
  forward_kinematics<Pack>(mv, q, nullptr, nullptr, H, nullptr, nullptr);
  if (!all_finite(H, n)) return 1;
  scatter(H, n, g.outs[0] + r0 * g.out_stride, g.out_stride);
  return 0;
}

// Up to this many dofs, the forward-dynamics derivatives' factor and solves run on Packs too (W lanes per
// operation on contiguous rows of Packs; measured per state on one thread: panda 1.97 → 1.06 µs, solo12
// 5.1 → 3.4, talos (nv = 50) 44 → 30); above it, lane by lane on each row's own nv² blocks (the packed
// 6 nv² scratch, 1.5 MB at nv = 64 with 8 lanes, would outgrow the caches).
constexpr int PACKED_SOLVES_MAX_NV = 64;

// Whether the group's rows of the first two outputs (∂/∂q and ∂/∂q̇), just written and still in the caches, are
// finite: a group whose finite input overflowed is redone row by row, and the row's status says where.
inline bool rows_finite(const fdgroup::GroupArgs& g, std::int64_t at, size_t n2) {
  for (int lane = 0; lane < PACK_WIDTH; ++lane) {
    const std::int64_t row = at + lane * g.out_stride;
    if (!all_finite(g.outs[0] + row, n2) || !all_finite(g.outs[1] + row, n2)) return false;
  }
  return true;
}

// ∂τ/∂q, ∂τ/∂q̇ and M of W rows: the analytical RNEA derivatives instantiated for Pack.
inline std::int64_t rnea_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nv = mv.nv, n2 = nv * nv;
  // a large batch: into Packs (3 nv² of them), then streamed out in whole lines; else straight into the rows
  const bool stream = g.stream && mv.nv <= PACKED_SOLVES_MAX_NV;
  const GroupState st = gather_state(g, r0, stream ? 3 * n2 : 0);
  const Pack *q = st.q, *v = st.v, *a = st.a, *f = st.f;
  const std::int64_t at = r0 * g.out_stride;
  if (stream) {
    Pack* dq = st.rest;
    Pack* dv = dq + n2;
    Pack* M = g.outs[2] ? dv + n2 : nullptr;
    rnea_derivatives_to(mv, q, v, a, f, g.gravity, StateOut<Pack>{{dq, dv, M}});
    if (!all_finite(dq, 2 * n2)) return 1;  // finite input overflowed in some lane: redone row by row, which says where
    scatter_lines(dq, n2, g.outs[0] + at, g.out_stride);
    scatter_lines(dv, n2, g.outs[1] + at, g.out_stride);
    if (M) scatter_lines(M, n2, g.outs[2] + at, g.out_stride);
    return 0;
  }
  rnea_derivatives_to(mv, q, v, a, f, g.gravity,
                      LanesOut{{g.outs[0] + at, g.outs[1] + at, g.outs[2] ? g.outs[2] + at : nullptr}, g.out_stride});
  return rows_finite(g, at, n2) ? 0 : 1;
}

// q̈, ∂q̈/∂q, ∂q̈/∂q̇ and M⁻¹ of W rows: the derivative kernel on Packs, then the factor and solves on Packs
// (small nv) or lane by lane, with the same templates as one state (bit-identical lanes).
inline std::int64_t aba_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nv = mv.nv, n2 = nv * nv;
  const bool packed = mv.nv <= PACKED_SOLVES_MAX_NV;
  const int* lambda = dof_tree(mv).lambda.data();
  const GroupState st = gather_state(g, r0, 2 * nv + (packed ? 6 * n2 : 0));
  const Pack *q = st.q, *v = st.v, *tau = st.a, *f = st.f;
  Pack* qdd = st.rest;
  Pack* h = qdd + nv;
  const std::int64_t at = r0 * g.out_stride;
  if (packed) {
    Pack* M = h + nv;
    Pack* dq = M + n2;
    Pack* dv = dq + n2;
    Pack* Minv = dv + n2;
    Pack* X = Minv + n2;
    auto solve = [&](const Pack* hh, Pack* out) { return factor_and_solve(mv, lambda, M, tau, hh, out); };
    if (forward_dynamics_derivatives_to(mv, q, v, f, g.gravity, StateOut<Pack>{{dq, dv, M}}, h, qdd, solve) >= 0)
      return 1;  // singular in some lane: redone row by row, which names it
    aba_derivatives_solves(mv, lambda, M, dq, dv, Minv, X);
    if (!all_finite(dq, 2 * n2)) return 1;  // finite input overflowed in some lane: redone row by row
    auto put = g.stream ? scatter_lines : scatter;
    put(dq, n2, g.outs[0] + at, g.out_stride);
    put(dv, n2, g.outs[1] + at, g.out_stride);
    put(Minv, n2, g.outs[2] + at, g.out_stride);
    return 0;
  }
  thread_local std::vector<double> M, X, x, t, hl;
  M.resize(PACK_WIDTH * n2), X.resize(2 * n2), x.resize(nv), t.resize(nv), hl.resize(nv);
  auto solve = [&](const Pack* hh, Pack* out) -> int {
    for (int lane = 0; lane < PACK_WIDTH; ++lane) {
      for (size_t k = 0; k < nv; ++k) t[k] = tau[k][lane], hl[k] = hh[k][lane];
      const int bad = factor_and_solve(mv, lambda, M.data() + lane * n2, t.data(), hl.data(), x.data());
      if (bad >= 0) return bad;
      for (size_t k = 0; k < nv; ++k) out[k].set(lane, x[k]);
    }
    return -1;
  };
  if (forward_dynamics_derivatives_to(mv, q, v, f, g.gravity,
                                      LanesOut{{g.outs[0] + at, g.outs[1] + at, M.data()}, static_cast<std::int64_t>(n2)},
                                      h, qdd, solve) >= 0)
    return 1;  // singular in some lane: redone row by row, which names it
  for (int lane = 0; lane < PACK_WIDTH; ++lane) {
    const std::int64_t row = at + lane * g.out_stride;
    aba_derivatives_solves(mv, lambda, M.data() + lane * n2, g.outs[0] + row, g.outs[1] + row, g.outs[2] + row, X.data());
  }
  return rows_finite(g, at, n2) ? 0 : 1;
}

// q̈, λ and the KKT result of W rows under the contacts of g.contacts: contacts.hpp's kernel on Packs. A lane whose
// M or D (mu = 0) is singular fails the group, which is then redone row by row: each row gets the one-state
// result and status (the other lanes' results are the same bits either way).
inline std::int64_t contact_dynamics_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const fdgroup::ContactArgs& c = *g.contacts;
  const size_t nv = mv.nv, m = c.m;
  const GroupState st = gather_state(g, r0, nv + m);
  const Pack *q = st.q, *v = st.v, *tau = st.a, *f = st.f;
  Pack* qdd = st.rest;
  Pack* lam = qdd + nv;
  ContactResult<Pack> res;
  int bad_lanes = 0;
  if (contact_dynamics(mv, q, v, tau, f, c.specs, c.nc, c.mu, c.max_iter, c.tol, c.singular_tol, qdd, lam, res,
                       &bad_lanes) != OK || bad_lanes != 0)
    return 1;
  scatter(qdd, nv, g.outs[0] + r0 * g.out_stride, g.out_stride);
  scatter(lam, m, c.lam + r0 * static_cast<std::int64_t>(m), static_cast<std::int64_t>(m));
  const Pack info[2] = {res.iterations, res.residual};
  scatter(info, 2, c.info + 2 * r0, 2);
  return 0;
}

// v⁺, Λ of W rows under the contacts of g.contacts with its restitution: contacts.hpp's impulse kernel on Packs. A
// lane whose M or D is singular fails the group, which is then redone row by row.
inline std::int64_t impulse_dynamics_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const fdgroup::ContactArgs& c = *g.contacts;
  const size_t nv = mv.nv, m = c.m;
  const GroupState st = gather_state(g, r0, nv + m);
  Pack* const outs[2] = {st.rest, st.rest + nv};
  if (impulse_dynamics(mv, st.q, st.v, c.specs, c.nc, c.restitution, c.singular_tol, outs[0], outs[1]) != OK ||
      !all_finite(st.rest, nv + m))
    return 1;
  const size_t len[2] = {nv, m};
  scatter_outputs(g, r0, outs, len, 2);
  return 0;
}

// q̈, λ and their derivatives ∂q̈/∂(q, q̇, τ) (nv, nv), ∂λ/∂(q, q̇, τ) (m, nv) of W rows under the contacts of
// g.contacts: contacts.hpp's solve and contact_derivatives.hpp's kernel on Packs. A lane whose M or D is singular, or
// whose solve did not converge, fails the group, which is then redone row by row (each row its one-state result
// and status; the other lanes' results are the same bits either way).
inline std::int64_t contact_dynamics_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const fdgroup::ContactArgs& c = *g.contacts;
  const size_t nv = mv.nv, m = c.m, n2 = nv * nv, mn = m * nv;
  const GroupState st = gather_state(g, r0, nv + m + 3 * n2 + 3 * mn);
  const Pack *q = st.q, *v = st.v, *tau = st.a, *f = st.f;
  Pack* qdd = st.rest;
  Pack* lam = qdd + nv;
  Pack* d = lam + m;
  ContactResult<Pack> res;
  int bad_lanes = 0;
  if (contact_dynamics(mv, q, v, tau, f, c.specs, c.nc, c.mu, c.max_iter, c.tol, c.singular_tol, qdd, lam, res,
                       &bad_lanes) != OK || bad_lanes != 0 || lanes_le(res.iterations, 0.0))
    return 1;  // (iterations −1: dependent contacts, −2: not converged, in some lane)
  Pack* const outs[8] = {d, d + n2, d + 2 * n2, d + 3 * n2, d + 3 * n2 + mn, d + 3 * n2 + 2 * mn, qdd, lam};
  if (contact_dynamics_derivatives(mv, q, v, f, qdd, lam, c.specs, c.nc, c.m, c.singular_tol, outs) != OK ||
      !all_finite(d, 3 * n2 + 3 * mn))
    return 1;
  const size_t len[8] = {n2, n2, n2, mn, mn, mn, nv, m};
  scatter_outputs(g, r0, outs, len, 8);
  return 0;
}

// v⁺, Λ and their derivatives ∂v⁺/∂(q, v⁻) (nv, nv), ∂Λ/∂(q, v⁻) (m, nv) of W rows under the contacts of g.contacts
// with its restitution: contact_derivatives.hpp's impulse kernel on Packs. A lane whose M or D is singular fails the
// group, which is then redone row by row.
inline std::int64_t impulse_dynamics_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const fdgroup::ContactArgs& c = *g.contacts;
  const size_t nv = mv.nv, m = c.m, n2 = nv * nv, mn = m * nv, total = 2 * n2 + 2 * mn + nv + m;
  const GroupState st = gather_state(g, r0, total);
  Pack* d = st.rest;
  Pack* const outs[6] = {d, d + n2, d + 2 * n2, d + 2 * n2 + mn, d + 2 * n2 + 2 * mn, d + 2 * n2 + 2 * mn + nv};
  if (impulse_dynamics_derivatives(mv, st.q, st.v, c.specs, c.nc, c.m, c.restitution, c.singular_tol, outs) != OK ||
      !all_finite(d, total))
    return 1;
  const size_t len[6] = {n2, n2, mn, mn, nv, m};
  scatter_outputs(g, r0, outs, len, 6);
  return 0;
}

// Λ (m, m) of W rows for the frames of g.contacts: contacts.hpp's kernel on Packs; a lane whose M or J M⁻¹ Jᵀ + μ 1
// is singular fails the group, redone row by row.
inline std::int64_t operational_space_inertia_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const fdgroup::ContactArgs& c = *g.contacts;
  const size_t nq = mv.nq, m2 = static_cast<size_t>(c.m) * c.m;
  Lanes& L = thread_lanes(nq + m2);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  Pack* Lambda = L.space(nq);
  if (operational_space_inertia(mv, q, c.specs, c.nc, c.mu, c.singular_tol, Lambda) != OK) return 1;
  scatter(Lambda, m2, g.outs[0] + r0 * g.out_stride, g.out_stride);
  return 0;
}

// (∂T/∂q, ∂T/∂q̇) of W rows (energy.hpp) — featherdyn.torch's and featherdyn.jax's crba gradients call it on
// 2 nv rows a state.
inline std::int64_t kinetic_energy_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv;
  Lanes& L = thread_lanes(nq + 3 * nv);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  const Pack* v = L.gather(g.V, r0, nv, nq);
  Pack* dq = L.space(nq + nv);
  Pack* dv = dq + nv;
  kinetic_energy_derivatives(mv, q, v, dq, dv);
  if (!all_finite(dq, 2 * nv)) return 1;
  scatter(dq, nv, g.outs[0] + r0 * g.out_stride, g.out_stride);
  scatter(dv, nv, g.outs[1] + r0 * g.out_stride, g.out_stride);
  return 0;
}

// The gradients of wᵀτ and wᵀq̈ (vjp.hpp) of W rows — the frameworks' reverse mode of rnea and aba.
template <bool Forward>
inline std::int64_t dynamics_vjp_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv, nf = 6 * static_cast<size_t>(mv.nb);
  Lanes& L = thread_lanes(nq + 6 * nv + nf);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  const Pack* v = L.gather(g.V, r0, nv, nq);
  const Pack* a = L.gather(g.A, r0, nv, nq + nv);
  const Pack* w = L.gather(g.W, r0, nv, nq + 2 * nv);
  const Pack* f = L.gather(g.FX, r0, nf, nq + 3 * nv);
  Pack* gq = L.space(nq + 3 * nv + nf);
  if constexpr (Forward) {
    if (aba_vjp(mv, q, v, a, w, f, g.gravity, gq, gq + nv, gq + 2 * nv) >= 0) return 1;  // singular in some lane
  } else {
    rnea_vjp(mv, q, v, a, w, f, g.gravity, gq, gq + nv, gq + 2 * nv);
  }
  if (!all_finite(gq, 3 * nv)) return 1;
  scatter(gq, nv, g.outs[0] + r0 * g.out_stride, g.out_stride);
  scatter(gq + nv, nv, g.outs[1] + r0 * g.out_stride, g.out_stride);
  scatter(gq + 2 * nv, nv, g.outs[2] + r0 * g.out_stride, g.out_stride);
  return 0;
}

// ∂⟨W, M⟩/∂q of W rows (vjp.hpp) — the frameworks' reverse mode of crba and mass_matrix_inverse.
inline std::int64_t crba_vjp_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv;
  Lanes& L = thread_lanes(nq + nv * nv + nv);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  const Pack* W = L.gather(g.W, r0, nv * nv, nq);
  Pack* grad = L.space(nq + nv * nv);
  crba_vjp(mv, q, W, grad);
  if (!all_finite(grad, nv)) return 1;
  scatter(grad, nv, g.outs[0] + r0 * g.out_stride, g.out_stride);
  return 0;
}

// Kernels of k (6, nv) or (3, nv) results (kinematics_derivatives.hpp), all of one stride: the results into Packs,
// checked, then scattered to g.outs.
inline std::int64_t put_results(const fdgroup::GroupArgs& g, std::int64_t r0, const Pack* x, int k, size_t n) {
  if (!all_finite(x, k * n)) return 1;  // finite input overflowed in some lane: redone row by row, which says where
  auto put = g.stream ? scatter_lines : scatter;
  for (int o = 0; o < k; ++o) put(x + o * n, n, g.outs[o] + r0 * g.out_stride, g.out_stride);
  return 0;
}

// A frame's velocity and acceleration derivatives (eight (6, nv), declarations_kinematics.hpp's order: J in the
// second, fifth and eighth) of W rows.
inline std::int64_t kinematics_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv, n = 6 * nv;
  Lanes& L = thread_lanes(nq + 2 * nv + 8 * n);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  const Pack* v = L.gather(g.V, r0, nv, nq);
  const Pack* a = L.gather(g.A, r0, nv, nq + nv);
  Pack* x = L.space(nq + 2 * nv);
  Pack* const outs[6] = {x, x + n, x + 2 * n, x + 3 * n, x + 5 * n, x + 6 * n};
  kinematics_derivatives(mv, q, v, a, g.frame, nullptr, g.reference, outs);
  std::copy_n(x + n, n, x + 4 * n);
  std::copy_n(x + n, n, x + 7 * n);
  return put_results(g, r0, x, 8, n);
}

// (∂c/∂q, ∂ċ/∂q) (3, nv) of W rows; a tree without mass fails the group (row by row: NO_MASS).
inline std::int64_t center_of_mass_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv, n = 3 * nv;
  const double mass = total_mass(mv);
  if (mass == 0.0) return 1;
  Lanes& L = thread_lanes(nq + nv + 2 * n);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  const Pack* v = L.gather(g.V, r0, nv, nq);
  Pack* x = L.space(nq + nv);
  center_of_mass_derivatives(mv, q, v, mass, x, x + n);
  return put_results(g, r0, x, 2, n);
}

// The centroidal momentum's and its rate's derivatives (four (6, nv)) of W rows; without mass as above.
inline std::int64_t centroidal_dynamics_derivatives_group(const fdgroup::GroupArgs& g, std::int64_t r0) {
  const ModelView& mv = *g.mv;
  const size_t nq = mv.nq, nv = mv.nv, n = 6 * nv;
  const double mass = total_mass(mv);
  if (mass == 0.0) return 1;
  Lanes& L = thread_lanes(nq + 2 * nv + 4 * n);
  const Pack* q = L.gather(g.Q, r0, nq, 0);
  const Pack* v = L.gather(g.V, r0, nv, nq);
  const Pack* a = L.gather(g.A, r0, nv, nq + nv);
  Pack* x = L.space(nq + 2 * nv);
  Pack* const outs[4] = {x, x + n, x + 2 * n, x + 3 * n};
  centroidal_dynamics_derivatives(mv, q, v, a, mass, outs);
  return put_results(g, r0, x, 4, n);
}

inline fdgroup::GroupKernels group_kernels(const char* isa) {
  return {isa, PACK_WIDTH, &rnea_group, &crba_group, &aba_group, &fk_group, &rnea_derivatives_group,
          &rnea_derivatives<double>, &mass_matrix_inverse, &aba_derivatives, &aba_derivatives_group,
          &contact_dynamics_group, &impulse_dynamics_group, &operational_space_inertia_group,
          &kinetic_energy_derivatives_group,
          &dynamics_vjp_group<false>, &dynamics_vjp_group<true>, &crba_vjp_group,
          &kinematics_derivatives_group, &center_of_mass_derivatives_group, &centroidal_dynamics_derivatives_group,
          &contact_dynamics_derivatives<double>, &impulse_dynamics_derivatives<double>, &rnea_second_derivatives,
          &aba_second_derivatives, &contact_dynamics_derivatives_group, &impulse_dynamics_derivatives_group,
          static_cast<fdgroup::FiniteFn>(&all_finite)};
}

}  // namespace fdcore

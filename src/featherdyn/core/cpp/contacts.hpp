// Point and frame contacts in one call: their rows, their drift and the constrained dynamics
// (reference: featherdyn/api/constraints.py, _one for PointContact / FrameContact, and
// featherdyn/algorithms/constrained.py for the solve).
//
//     point contact (3 rows):  J = the linear rows of the frame Jacobian in `ref`,
//                              γ = the classical acceleration of the frame's origin at q̈ = 0, in `ref`
//     frame contact (6 rows):  J = the frame Jacobian in `ref`, γ = the frame's spatial acceleration at q̈ = 0
//     c = −γ − K_d J q̇        (a contact's error e is zero: K_p has nothing to act on)
//
// then M q̈ + h = τ + Jᵀ λ, J q̈ = c by the Schur complement on M's LᵀL factor (ltl.hpp's kkt_solve, the
// same equations). Everything comes from one pass over the bodies, each joint transform computed once:
//
//   forward (i = 0 … nb−1):  the pose of body i in its parent and in its tree's root body (ʳR_i, ʳp_i);
//       CRBA's ʳS_i and ʳI_i (crba.hpp: the tree's root-body coordinates);
//       with q̇: v_i, the bias acceleration a_i at q̈ = 0 (RBDA §5.3) and RNEA's f_i (with gravity, f_ext),
//       in the same root-body coordinates
//   backward (i = nb−1 … 0): I^C_λ += I^C_i, τ_i = ʳS_iᵀ f_i, f_λ += f_i  → h = C q̇ + g − J_extᵀ f_ext
//   M in ltl.hpp's packed layout (row k: M_k at the ancestor dofs of k, then M_kk), factored in place
//
// A contact on body b has nonzero columns only on the chain of b's last dof (root … b), so its rows, and
// Y = J L⁻¹ (ltl_solve_Lt_chain_rows), are kept in that chain's positions, contiguous:
//
//     ʳJ column of dof k = ʳS_k shifted to the frame's origin,  then frame axes (LOCAL) or world axes (LWA);
//     WORLD: ⁰X_r ʳS_k (about the world origin)
//     z = L⁻ᵀ (τ − h),   J q̈_f = Y z,   D = J M⁻¹ Jᵀ = Y Yᵀ (only over the two chains' common prefix)
//     D λ = c − Y z,     q̈ = L⁻¹ (z + Yᵀ λ)
//
// With mu > 0 the proximal iterations of kkt_solve (Carpentier, Budhiraja & Mansard, RSS 2021). An impact
// (impulse_dynamics) is the same system without the velocity pass: τ − h = 0, c = −(1 + e) J v⁻.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "checks.hpp"
#include "contact_spec.hpp"
#include "frames.hpp"
#include "ltl.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

// The kernels below are templates on the scalar S: double (one state) or Pack (PACK_WIDTH states, the batches of
// simd_groups.hpp), with the same operations in the same order (lanes bit-identical to one state). Everything
// that decides the control flow (the chains, the rows, the common prefixes) depends on the model and the specs
// only, so it is the same in every lane; what depends on the state (a pivot of M or of D, the proximal
// iterations' stop) is a lane mask.
template <class S>
struct ContactWork {
  std::vector<Mat3<S>> Rp, Rr;      // body i in its parent (X_up = plux(Rpᵀ, pp)), in its root body
  std::vector<Vec3<S>> pp, pr, g;   // g_r: a₀'s linear part [ʳR_0 (−g)] for a root body r
  std::vector<int> root;            // the root body of body i's tree
  std::vector<RigidInertia<S>> IC;  // ʳI_i, then I^C_i (root-body coordinates)
  std::vector<Motion<S>> Sr, v, a;  // ʳS of each dof; v_i, a_i (q̈ = 0, no gravity) in root-body coordinates
  std::vector<Force<S>> f;
  std::vector<S> P, dinv, J, Y, c, th, z, D, D0, rhs, x;
  std::vector<int> first, len, last, common;  // per contact: first row, chain length, last dof; common prefixes
  std::vector<ArticulatedInertia<S>> IA;      // Λ: I^A_i with the dofs off the frames' chains eliminated
  std::vector<char> on_chain;                 // Λ: per dof, on the chain of some frame
  std::vector<char> started;                  // Λ: per body, I^A_i holds ʳI_i (and the children added so far)
  void resize(size_t nb) {
    if (Rp.size() < nb)
      Rp.resize(nb), Rr.resize(nb), pp.resize(nb), pr.resize(nb), g.resize(nb), root.resize(nb), IC.resize(nb),
          v.resize(nb), a.resize(nb), f.resize(nb);
  }
};

// The forward and backward passes of the file comment. With qd == nullptr only the kinematics and the
// composite inertias (with composite == false: each body's own ʳI_i); with h != nullptr also
// h (nv,) = RNEA(q, q̇, 0) with gravity and f_ext (nb, 6) or nullptr.
// Velocities, accelerations and forces are in root-body coordinates too (any coordinates fixed in space at
// this instant serve the recursion, RBDA §5.3 in a fixed frame): v_i = v_λ + ʳS_i q̇_i, a_i = a_λ + v_i × ʳS_i q̇_i,
// f_i = ʳI_i (a_i + a₀) + v_i ×* ʳI_i v_i − ʳX_i* f_i^ext, f_λ += f_i, τ_i = ʳS_iᵀ f_i: no transform per body.
template <class S>
void contact_pass(const ModelView& mv, const S* q, const S* qd, const S* f_ext, ContactWork<S>& w, S* h,
                  bool composite = true) {
  const int nb = mv.nb;
  w.Sr.resize(static_cast<size_t>(mv.nv));
  const Vec3<S> g0{S(-mv.gravity[0]), S(-mv.gravity[1]), S(-mv.gravity[2])};  // a₀ = [0; −g] in world coordinates
  const Vec3<S> zero3{S(0.0), S(0.0), S(0.0)};
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i], iv = mv.idx_v[i], ni = mv.nv_i[i];
    pose_in_parent(mv, i, q, w.Rp[i], w.pp[i]);
    const RigidInertia<S> I = body_inertia<S>(mv, i);
    if (lam == -1) {  // a root body: its own coordinates
      w.root[i] = i;
      w.Rr[i] = Mat3<S>::identity();
      w.pr[i] = zero3;
      w.IC[i] = I;
      w.g[i] = mul_transpose(w.Rp[i], g0);  // a₀ of the tree, [0; ʳR_0 (−g)]
      for (int c = 0; c < ni; ++c) w.Sr[iv + c] = S_col<S>(mv, i, c);
    } else {
      w.root[i] = w.root[lam];
      if (mv.parent[lam] == -1) {  // the parent is the root: ʳX_λ = 1
        w.Rr[i] = w.Rp[i];
        w.pr[i] = w.pp[i];
      } else {
        w.Rr[i] = w.Rr[lam] * w.Rp[i];
        w.pr[i] = w.pr[lam] + w.Rr[lam] * w.pp[i];
      }
      w.IC[i] = transform_to_parent(Xform<S>{w.Rr[i].transpose(), w.pr[i]}, I);
      if (mv.jtype[i] == REVOLUTE) {  // S = [axis; 0]: ʳS = [ʳR a; ʳp × ʳR a]
        const Vec3<S> wr = w.Rr[i] * load3<S>(mv.axis + 3 * i);
        w.Sr[iv] = {wr, cross(w.pr[i], wr)};
      } else {
        for (int c = 0; c < ni; ++c) {
          const Motion<S> s = S_col<S>(mv, i, c);
          const Vec3<S> wr = w.Rr[i] * s.w;
          w.Sr[iv + c] = {wr, w.Rr[i] * s.v + cross(w.pr[i], wr)};
        }
      }
    }
    if (qd == nullptr) continue;
    Motion<S> vJ{zero3, zero3};
    for (int c = 0; c < ni; ++c) vJ = vJ + Motion<S>{qd[iv + c] * w.Sr[iv + c].w, qd[iv + c] * w.Sr[iv + c].v};
    if (lam == -1) {
      w.v[i] = vJ;
      w.a[i] = {zero3, zero3};  // v × v = 0
    } else {
      w.v[i] = w.v[lam] + vJ;
      w.a[i] = w.a[lam] + cross_motion(w.v[i], vJ);
    }
    if (h == nullptr) continue;
    const RigidInertia<S>& Ir = w.IC[i];  // ʳI_i (the children are added in the backward pass)
    const Motion<S> ai{w.a[i].w, w.a[i].v + w.g[w.root[i]]};
    w.f[i] = Ir * ai + cross_force(w.v[i], Ir * w.v[i]);
    if (f_ext) {  // ʳX_i* f = [R n + p × R f; R f]
      const S* fx = f_ext + 6 * i;
      const Vec3<S> fr = w.Rr[i] * Vec3<S>{fx[3], fx[4], fx[5]};
      const Vec3<S> nr = w.Rr[i] * Vec3<S>{fx[0], fx[1], fx[2]} + cross(w.pr[i], fr);
      w.f[i] = w.f[i] - Force<S>{nr, fr};
    }
  }
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i], iv = mv.idx_v[i];
    if (lam != -1 && composite) w.IC[lam] = w.IC[lam] + w.IC[i];
    if (h == nullptr) continue;
    for (int c = 0; c < mv.nv_i[i]; ++c) h[iv + c] = dot(w.Sr[iv + c], w.f[i]);
    if (lam != -1) w.f[lam] += w.f[i];
  }
}

// M in the packed layout of ltl.hpp from the pass's composite inertias (crba.hpp's entries: M_kj = ʳS_jᵀ I^C ʳS_k
// for j an ancestor dof of k or k itself, plus the armature on the diagonal).
template <class S>
void mass_matrix_packed(const ModelView& mv, const DofTree& t, const ContactWork<S>& w, S* P) {
  for (int i = 0; i < mv.nb; ++i) {
    for (int c = 0; c < mv.nv_i[i]; ++c) {
      const int k = mv.idx_v[i] + c, dk = t.depth[k];
      const Force<S> F = w.IC[i] * w.Sr[k];
      S* row = P + t.off[k];
      const int* ch = t.chain.data() + t.off[k];
      for (int s = 0; s < dk; ++s) row[s] = dot(w.Sr[ch[s]], F);
      row[dk] = dot(w.Sr[k], F);
      if (mv.armature) row[dk] += S(mv.armature[k]);
    }
  }
}

// The last dof on the way from body b to the root (−1: none, b is fixed to the world).
inline int last_dof(const ModelView& mv, int b) {
  for (int i = b; i != -1; i = mv.parent[i])
    if (mv.nv_i[i] > 0) return mv.idx_v[i] + mv.nv_i[i] - 1;
  return -1;
}

// The frame's rows (6, len) in chain positions of dof `kd` (len = depth + 1; column s is dof chain[s]) in `ref`,
// all six rows [ω; v], from the pass's ʳS (see the file comment).
template <class S>
void frame_rows(const ModelView& mv, const DofTree& t, const ContactWork<S>& w, int frame, int ref, int kd, S* J6) {
  if (kd < 0) return;
  const int b = mv.frame_body[frame], len = t.depth[kd] + 1, r = w.root[b];
  const int* ch = t.chain.data() + t.off[kd];
  const Mat3<S> Rf = w.Rr[b] * load9<S>(mv.frame_R + 9 * frame);            // ʳR_f
  const Vec3<S> pf = w.pr[b] + w.Rr[b] * load3<S>(mv.frame_p + 3 * frame);  // ʳp_f
  const Mat3<S>& R0 = w.Rp[r];                                                // ⁰R_r
  for (int s = 0; s < len; ++s) {
    const Motion<S>& Sc = w.Sr[ch[s]];
    Vec3<S> om, vel;
    if (ref == WORLD) {
      om = R0 * Sc.w;
      vel = R0 * Sc.v + cross(w.pp[r], om);
    } else {
      const Vec3<S> vf = Sc.v + cross(Sc.w, pf);  // the column's velocity of the point at the frame's origin
      om = ref == LOCAL ? mul_transpose(Rf, Sc.w) : R0 * Sc.w;
      vel = ref == LOCAL ? mul_transpose(Rf, vf) : R0 * vf;
    }
    J6[0 * len + s] = om.x, J6[1 * len + s] = om.y, J6[2 * len + s] = om.z;
    J6[3 * len + s] = vel.x, J6[4 * len + s] = vel.y, J6[5 * len + s] = vel.z;
  }
}

// The frame's motion at q̈ = 0 in `ref`: spatial (rows == 6) or classical (rows == 3) acceleration, from the body's
// v_b, a_b (root-body coordinates) and the frame's pose in the root body and the root's in the world.
template <class S>
Motion<S> contact_drift(const ModelView& mv, const ContactWork<S>& w, int frame, int ref, int rows) {
  const int b = mv.frame_body[frame];
  if (b == -1) return {{S(0.0), S(0.0), S(0.0)}, {S(0.0), S(0.0), S(0.0)}};
  const Mat3<S> Rrf = w.Rr[b] * load9<S>(mv.frame_R + 9 * frame);            // ʳR_f
  const Vec3<S> prf = w.pr[b] + w.Rr[b] * load3<S>(mv.frame_p + 3 * frame);  // ʳp_f
  const Xform<S> f_X_r{Rrf.transpose(), prf};
  const Motion<S> vf = f_X_r.apply(w.v[b]), af = f_X_r.apply(w.a[b]);
  Motion<S> out = af;
  if (rows == 3) out.v = af.v + cross(vf.w, vf.v);
  if (ref == LOCAL) return out;
  const int r = w.root[b];
  const Mat3<S> Rf = w.Rp[r] * Rrf;  // ⁰R_f
  if (ref == LOCAL_WORLD_ALIGNED) return {Rf * out.w, Rf * out.v};
  const Vec3<S> pf = w.pp[r] + w.Rp[r] * prf;  // ⁰p_f
  const Xform<S> f_X_0{Rf.transpose(), pf};    // ⁰X_f = f_X_0⁻¹
  const Motion<S> a0 = f_X_0.apply_inverse(af);
  if (rows == 6) return a0;
  const Motion<S> v0 = f_X_0.apply_inverse(vf);
  return {a0.w, a0.v + cross(v0.w, v0.v)};
}

// The contacts' rows in chain positions: w.J (m rows, row r of contact k at w.first[k], w.len[k] entries each,
// consecutive), and the common chain prefix of each pair of contacts w.common (nc, nc). Returns m.
template <class S>
int contact_rows(const ModelView& mv, const DofTree& t, const ContactSpec* specs, int nc, ContactWork<S>& w) {
  w.first.resize(nc + 1);
  w.len.resize(nc);
  w.last.resize(nc);
  w.common.resize(static_cast<size_t>(nc) * nc);
  int m = 0, size = 0;
  for (int k = 0; k < nc; ++k) {
    const int b = mv.frame_body[specs[k].frame];
    w.last[k] = b == -1 ? -1 : last_dof(mv, b);
    w.len[k] = w.last[k] == -1 ? 0 : t.depth[w.last[k]] + 1;
    w.first[k] = size;
    size += specs[k].rows * w.len[k];
    m += specs[k].rows;
  }
  w.first[nc] = size;
  w.J.resize(static_cast<size_t>(size) + 6 * static_cast<size_t>(mv.nv));  // and a 6-row scratch at the end
  S* J6 = w.J.data() + size;
  for (int k = 0; k < nc; ++k) {
    const ContactSpec& s = specs[k];
    const int len = w.len[k];
    frame_rows(mv, t, w, s.frame, s.ref, w.last[k], J6);
    std::copy(J6 + (6 - s.rows) * len, J6 + 6 * len, w.J.data() + w.first[k]);
    for (int l = 0; l < nc; ++l) {  // the chains of k and l agree up to their lowest common ancestor dof
      int n = 0;
      if (l < k) {
        n = w.common[l * nc + k];
      } else if (w.last[k] >= 0 && w.last[l] >= 0) {
        const int* a = t.chain.data() + t.off[w.last[k]];
        const int* c = t.chain.data() + t.off[w.last[l]];
        const int nmax = std::min(w.len[k], w.len[l]);
        while (n < nmax && a[n] == c[n]) ++n;
      }
      w.common[k * nc + l] = n;
    }
  }
  return m;
}

// D = Y Yᵀ (m, m) for the solved rows Y (the layout of w.J): row pairs only over their chains' common prefix.
template <class S>
void delassus_rows(const ContactSpec* specs, int nc, const ContactWork<S>& w, const S* Y, int m, S* D) {
  int r = 0;
  for (int k = 0; k < nc; ++k) {
    for (int i = 0; i < specs[k].rows; ++i, ++r) {
      const S* yr = Y + w.first[k] + i * w.len[k];
      int c = 0;
      for (int l = 0; l <= k; ++l) {
        const int n = w.common[k * nc + l];
        for (int j = 0; j < specs[l].rows && c <= r; ++j, ++c) {
          const S* yc = Y + w.first[l] + j * w.len[l];
          S x(0.0);
          for (int s = 0; s < n; ++s) x = x + yr[s] * yc[s];
          D[r * m + c] = D[c * m + r] = x;
        }
      }
    }
  }
}

// Y = J L⁻¹: each row solved along its chain (ltl_solve_Lt_chain_rows).
template <class S>
void solve_rows(const DofTree& t, const S* P, const ContactSpec* specs, int nc, ContactWork<S>& w) {
  const S* dinv = w.dinv.data();
  w.Y.assign(w.J.begin(), w.J.begin() + w.first[nc]);
  for (int k = 0; k < nc; ++k)
    if (w.last[k] >= 0)
      ltl_solve_Lt_chain_rows<S>(t, P, dinv, w.last[k], w.Y.data() + w.first[k], specs[k].rows, w.len[k]);
}

// Σ_u a[u] x[chain[u]]: a row kept in chain positions (J or Y) against a joint-space vector x.
template <class S>
S chain_dot(const S* a, const int* chain, int len, const S* x) {
  S s(0.0);
  for (int u = 0; u < len; ++u) s += a[u] * x[chain[u]];
  return s;
}

// f(row, at, chain, len) for every constraint row, in order: `at` its offset in J and Y (chain positions),
// `chain` and `len` its contact's chain of dofs.
template <class S, class F>
inline void for_contact_rows(const DofTree& t, const ContactSpec* specs, int nc, const ContactWork<S>& w, F f) {
  int row = 0;
  for (int k = 0; k < nc; ++k) {
    const int len = w.len[k];
    const int* ch = len > 0 ? t.chain.data() + t.off[w.last[k]] : nullptr;
    for (int r = 0; r < specs[k].rows; ++r, ++row) f(row, w.first[k] + r * len, ch, len);
  }
}

// The KKT solve's outcome per lane: iterations (≥ 1; −1: D singular (mu = 0), −2: not converged) and ‖J q̈ − c‖∞.
template <class S>
struct ContactResult {
  S iterations{0.0};
  S residual{0.0};
};

// Steps 1 and 2 of the file comment (the drift c aside): the pass (with q̇: v, a and h = RNEA(q, q̇, 0) into w.th),
// M packed and factored, the contacts' rows J and Y = J L⁻¹ in chain positions. m = Σ rows. Returns OK, or a
// SINGULAR status naming the body whose pivot of M failed (for a Pack: in some lane).
template <class S>
std::int64_t contact_system(const ModelView& mv, const DofTree& t, const S* q, const S* qd, const S* f_ext,
                            const ContactSpec* specs, int nc, ContactWork<S>& w, int& m) {
  const int nv = mv.nv;
  w.th.resize(nv);
  w.P.resize(static_cast<size_t>(t.off[nv]));
  w.dinv.resize(nv);
  contact_pass(mv, q, qd, f_ext, w, qd != nullptr ? w.th.data() : nullptr);
  mass_matrix_packed(mv, t, w, w.P.data());
  const int bad = ltl_factor_packed<S>(t, w.P.data(), w.dinv.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  m = contact_rows(mv, t, specs, nc, w);
  solve_rows(t, w.P.data(), specs, nc, w);
  w.c.resize(m);
  return OK;
}

// Steps 3 (its z given) to 5 of the file comment: with z = L⁻ᵀ (τ − h) in w.z and c in w.c, the right-hand side
// c − Y z, D = Y Yᵀ, λ (one solve, or the proximal iterations with mu > 0), q̈ = L⁻¹ (z + Yᵀ λ) and the residual.
// Returns the lanes whose D failed its Cholesky pivot (mu = 0: dependent rows; 1 for a double), with
// res.iterations = −1 and q̈, λ left as they were; 0 otherwise.
template <class S>
int contact_solve(const ModelView& mv, const DofTree& t, const ContactSpec* specs, int nc, int m, double mu,
                  int max_iter, double tol, double singular_tol, ContactWork<S>& w, S* qdd, S* lam,
                  ContactResult<S>& res) {
  const int nv = mv.nv;
  w.rhs.resize(m);
  w.D.resize(static_cast<size_t>(m) * m);
  w.D0.resize(static_cast<size_t>(m) * m);
  w.x.resize(std::max(m, nv));
  for_contact_rows(t, specs, nc, w, [&](int i, int at, const int* ch, int len) {
    w.rhs[i] = w.c[i] - chain_dot(w.Y.data() + at, ch, len, w.z.data());
  });
  S* D = w.D.data();
  delassus_rows(specs, nc, w, w.Y.data(), m, D);
  // λ: one solve (mu = 0), or kkt_solve's proximal iterations, each lane stopping at its own iteration
  std::copy(D, D + static_cast<size_t>(m) * m, w.D0.data());
  S rhs_size(1.0);
  for (int r = 0; r < m; ++r) rhs_size = lane_max(rhs_size, lane_abs(w.rhs[r]));
  for (int i = 0; i < m; ++i) D[i * m + i] += S(mu);
  res = ContactResult<S>{};
  const int failed = dense_cholesky<S>(D, m, mu > 0.0 ? 0.0 : singular_tol);
  if (failed) {
    res.iterations = S(-1.0);
    return failed;
  }
  S* x = w.x.data();
  for (int r = 0; r < m; ++r) lam[r] = S(0.0);
  const int iters = mu > 0.0 ? std::max(1, max_iter) : 1;
  int done = 0;  // the lanes whose iterations have stopped (their λ is final)
  for (int it = 1; it <= iters; ++it) {
    for (int r = 0; r < m; ++r) x[r] = w.rhs[r] + S(mu) * lam[r];
    dense_cholesky_solve<S>(D, m, x);
    for (int r = 0; r < m; ++r) lam[r] = blend(done, lam[r], x[r]);
    res.iterations = blend(done, res.iterations, S(it));
    if (mu <= 0.0) break;
    S dual(0.0);  // ‖D λ − (c − J q̈_f)‖∞
    for (int r = 0; r < m; ++r) {
      S y = -w.rhs[r];
      for (int k = 0; k < m; ++k) y += w.D0[r * m + k] * lam[k];
      dual = lane_max(dual, lane_abs(y));
    }
    done |= lanes_at_most(dual, S(tol) * rhs_size);
    if (done == all_lanes<S>()) break;
    if (it == iters) res.iterations = blend(done, res.iterations, S(-2.0));
  }
  // q̈ = L⁻¹ (z + Yᵀ λ), and the residual ‖J q̈ − c‖∞
  for (int j = 0; j < nv; ++j) qdd[j] = w.z[j];
  for_contact_rows(t, specs, nc, w, [&](int i, int at, const int* ch, int len) {
    const S* yr = w.Y.data() + at;
    for (int u = 0; u < len; ++u) qdd[ch[u]] += yr[u] * lam[i];
  });
  ltl_solve_L_packed<S>(t, w.P.data(), w.dinv.data(), qdd);
  for_contact_rows(t, specs, nc, w, [&](int i, int at, const int* ch, int len) {
    res.residual = lane_max(res.residual, lane_abs(chain_dot(w.J.data() + at, ch, len, qdd) - w.c[i]));
  });
  return 0;
}

// q̈ (nv,), λ (m,), and the KKT result for the contacts `specs` at (q, q̇, τ, f_ext); m = Σ rows.
// Returns OK, or a SINGULAR status naming the body whose pivot of M failed (for a Pack: in some lane). A D whose
// Cholesky pivot fails (mu = 0: dependent rows) sets iterations = −1 (for a Pack: in every lane, with `bad_lanes`
// the lanes that failed) and leaves q̈ and λ as they were.
template <class S>
std::int64_t contact_dynamics(const ModelView& mv, const S* q, const S* qd, const S* tau, const S* f_ext,
                              const ContactSpec* specs, int nc, double mu, int max_iter, double tol,
                              double singular_tol, S* qdd, S* lam, ContactResult<S>& res, int* bad_lanes = nullptr) {
  const int nv = mv.nv;
  const DofTree& t = dof_tree(mv);
  ContactWork<S>& w = thread_workspace<ContactWork<S>>(mv.nb);
  int m = 0;
  if (const std::int64_t st = contact_system(mv, t, q, qd, f_ext, specs, nc, w, m); st != OK) return st;
  // c = −γ − K_d J q̇ (γ: the frame's drift, contact_drift)
  int row = 0;
  for (int k = 0; k < nc; ++k) {
    const ContactSpec& s = specs[k];
    const Motion<S> g = contact_drift(mv, w, s.frame, s.ref, s.rows);
    const S gam[6] = {g.w.x, g.w.y, g.w.z, g.v.x, g.v.y, g.v.z};
    const int len = w.len[k];
    const int* ch = len > 0 ? t.chain.data() + t.off[w.last[k]] : nullptr;
    for (int r = 0; r < s.rows; ++r, ++row)
      w.c[row] = -gam[6 - s.rows + r] - S(s.kd) * chain_dot(w.J.data() + w.first[k] + r * len, ch, len, qd);
  }
  // z = L⁻ᵀ (τ − h)
  w.z.resize(nv);
  for (int j = 0; j < nv; ++j) w.z[j] = tau[j] - w.th[j];
  ltl_solve_Lt_packed<S>(t, w.P.data(), w.dinv.data(), w.z.data());
  const int failed = contact_solve(mv, t, specs, nc, m, mu, max_iter, tol, singular_tol, w, qdd, lam, res);
  if (failed && bad_lanes) *bad_lanes = failed;
  return OK;
}

// The impulse v⁺ (nv,), Λ (m,) of an impact with the contacts (restitution e, 0 ≤ e ≤ 1): the constrained
// dynamics' KKT system above with M (v⁺ − v⁻) = Jᵀ Λ and J v⁺ = −e J v⁻, that is τ − h = 0 (z = 0), q̈ → v⁺ − v⁻
// and c = −(1 + e) J v⁻:
//     Λ = −(1 + e) D⁻¹ J v⁻,   v⁺ = v⁻ + L⁻¹ Yᵀ Λ        (D = Y Yᵀ = J M⁻¹ Jᵀ, no velocity pass)
// Returns OK, SINGULAR (M), or CONSTRAINT (D singular: dependent contacts; for a Pack, in some lane).
template <class S>
std::int64_t impulse_dynamics(const ModelView& mv, const S* q, const S* vm, const ContactSpec* specs, int nc,
                              double e, double singular_tol, S* vp, S* Lam) {
  const int nv = mv.nv;
  const DofTree& t = dof_tree(mv);
  ContactWork<S>& w = thread_workspace<ContactWork<S>>(mv.nb);
  int m = 0;
  const std::int64_t st = contact_system(mv, t, q, static_cast<const S*>(nullptr), static_cast<const S*>(nullptr),
                                         specs, nc, w, m);
  if (st != OK) return st;
  const S minus_1e(-(1.0 + e));
  for_contact_rows(t, specs, nc, w, [&](int i, int at, const int* ch, int len) {
    w.c[i] = minus_1e * chain_dot(w.J.data() + at, ch, len, vm);
  });
  w.z.assign(nv, S(0.0));
  ContactResult<S> res;
  if (contact_solve(mv, t, specs, nc, m, 0.0, 1, 0.0, singular_tol, w, vp, Lam, res))
    return make_status(CONSTRAINT, ARG_OUT, m);
  for (int i = 0; i < nv; ++i) vp[i] = vm[i] + vp[i];
  return OK;
}

// Λ = (J M⁻¹ Jᵀ + μ 1)⁻¹ (m, m) for the frames of `specs` (6 rows each, the stacked frame Jacobians J).
//
// Y = J L⁻¹ reads only the rows of L on the frames' chains (the support), and eliminating every dof off the
// support leaves on the support rows the Schur complement, whose entries are those of M with each subtree
// hanging off the support carried by its articulated-body inertia instead of its composite one (RBDA §7.2;
// the support-only part of the extended force propagator of Wensing, Featherstone & Orin 2012). In root-body
// coordinates the articulated inertias add up with no transform:
//
//     I^A_i = ʳI_i + Σ_children I^A_j;   off the support, for each dof k of body i (last first):
//         U = I^A_i ʳS_k,   D = ʳS_kᵀ U + armature_k,   I^A_i −= U Uᵀ / D          (D: the LᵀL pivot of dof k)
//     on the support:  M_kj = ʳS_jᵀ I^A_i ʳS_k  (j an ancestor dof of k), then the packed factor of these rows
//
// so the subtrees off the frames' chains cost O(bodies) instead of the factor's O(depth²) per dof. Then
// J M⁻¹ Jᵀ = Y Yᵀ and its inverse through its Cholesky factor (M is never inverted). Returns OK, SINGULAR for
// M, or CONSTRAINT (index m) when J M⁻¹ Jᵀ + μ 1 has a pivot below singular_tol.
template <class S>
std::int64_t operational_space_inertia(const ModelView& mv, const S* q, const ContactSpec* specs, int nc, double mu,
                                       double singular_tol, S* Lambda) {
  const int nb = mv.nb, nv = mv.nv, m = 6 * nc;
  const DofTree& t = dof_tree(mv);
  ContactWork<S>& w = thread_workspace<ContactWork<S>>(nb);
  w.P.resize(static_cast<size_t>(t.off[nv]));
  w.dinv.resize(nv);
  w.IA.resize(nb);
  w.on_chain.assign(nv, 0);
  contact_pass<S>(mv, q, nullptr, nullptr, w, nullptr, false);
  for (int k = 0; k < nc; ++k) {
    const int b = mv.frame_body[specs[k].frame], kd = b == -1 ? -1 : last_dof(mv, b);
    for (int i = kd; i != -1 && !w.on_chain[i]; i = t.lambda[i]) w.on_chain[i] = 1;
  }
  // I^A_i starts as ʳI_i when its first child adds to it (or, for a leaf, at its own turn), written in place
  w.started.assign(nb, 0);
  for (int i = nb - 1; i >= 0; --i) {
    const int iv = mv.idx_v[i], lam = mv.parent[i];
    ArticulatedInertia<S>& IA = w.IA[i];
    if (!w.started[i]) IA.set_rigid(w.IC[i]);
    for (int c = mv.nv_i[i] - 1; c >= 0 && !w.on_chain[iv + c]; --c) {
      const Motion<S>& Sc = w.Sr[iv + c];
      const Force<S> U = IA * Sc;
      S D = dot(Sc, U);
      if (mv.armature) D += S(mv.armature[iv + c]);
      if (lanes_le(D, 0.0)) return make_status(SINGULAR, ARG_Q, i);
      const S d = S(1.0) / D;
      const Vec3<S> n = d * U.n, f = d * U.f;  // I^A −= U Uᵀ / D, block by block
      for (int r = 0; r < 3; ++r) {
        const S nr = r == 0 ? U.n.x : r == 1 ? U.n.y : U.n.z, fr = r == 0 ? U.f.x : r == 1 ? U.f.y : U.f.z;
        IA.A(r, 0) -= nr * n.x, IA.A(r, 1) -= nr * n.y, IA.A(r, 2) -= nr * n.z;
        IA.B(r, 0) -= nr * f.x, IA.B(r, 1) -= nr * f.y, IA.B(r, 2) -= nr * f.z;
        IA.C(r, 0) -= fr * f.x, IA.C(r, 1) -= fr * f.y, IA.C(r, 2) -= fr * f.z;
      }
    }
    if (lam == -1) continue;
    if (w.started[lam]) {
      w.IA[lam] += IA;
    } else {
      w.IA[lam].set_rigid_plus(w.IC[lam], IA);
      w.started[lam] = 1;
    }
  }
  for (int i = 0; i < nb; ++i) {  // the support rows of M (a body is on the support through its last dof)
    for (int c = 0; c < mv.nv_i[i]; ++c) {
      const int k = mv.idx_v[i] + c, dk = t.depth[k];
      if (!w.on_chain[k]) continue;
      const Force<S> F = w.IA[i] * w.Sr[k];
      S* row = w.P.data() + t.off[k];
      const int* ch = t.chain.data() + t.off[k];
      for (int s = 0; s < dk; ++s) row[s] = dot(w.Sr[ch[s]], F);
      row[dk] = dot(w.Sr[k], F);
      if (mv.armature) row[dk] += S(mv.armature[k]);
    }
  }
  const int bad = ltl_factor_packed<S>(t, w.P.data(), w.dinv.data(), w.on_chain.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  contact_rows(mv, t, specs, nc, w);
  solve_rows(t, w.P.data(), specs, nc, w);
  w.D.resize(static_cast<size_t>(m) * m);
  S* D = w.D.data();
  delassus_rows(specs, nc, w, w.Y.data(), m, D);
  for (int i = 0; i < m; ++i) D[i * m + i] += S(mu);
  if (dense_cholesky<S>(D, m, singular_tol)) return make_status(CONSTRAINT, ARG_OUT, m);
  w.D0.resize(static_cast<size_t>(m) * m);
  dense_cholesky_inverse<S>(D, m, w.D0.data(), Lambda);
  return OK;
}

}  // namespace fdcore

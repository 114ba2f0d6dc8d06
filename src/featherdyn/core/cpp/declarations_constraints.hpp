// The declared constraint algorithms (declare.hpp; docs/architecture.md, "One declaration per algorithm"): the
// Delassus matrix, the constrained KKT system of given rows, contacts' rows and solve in one call, and Λ of frames.
// Their length m (NM) is the call's: the rows of the given J (option ROWS), or the contacts' Σ rows (CONTACTS).
//
// The KKT solves report, besides q̈ and λ, info = [iterations, ‖J q̈ − c‖∞]: iterations ≥ 1, or −1 when D = J M⁻¹ Jᵀ
// is singular with mu = 0 (dependent rows), −2 when the proximal iterations did not reach `tol` in `max_iter`. Those
// are not statuses (a batch goes on past such a row); the caller raises (featherdyn/core: ConstraintError). With −1,
// q̈ and λ are zero: not a solution.
#pragma once

#include <algorithm>
#include <vector>

#include "aba.hpp"
#include "contact_derivatives.hpp"
#include "contacts.hpp"
#include "declare.hpp"
#include "ltl.hpp"
#include "rnea.hpp"

namespace fdcore {

// The singular joint (−1: none) of q and its D = Sᵀ Iᴬ S: ABA at rest (the articulated inertias depend on q only) —
// the detail of a SINGULAR status of every algorithm that factors or inverts M(q) (here, declarations.hpp's and
// declarations_second_order.hpp's).
inline std::int64_t singular_at_rest(const ModelView& mv, const double* const* in, const Options&, double* D36) {
  std::vector<double> zero(static_cast<size_t>(mv.nv), 0.0), qdd(static_cast<size_t>(mv.nv));
  return aba<double>(mv, in[0], zero.data(), zero.data(), nullptr, false, qdd.data(), D36);
}

namespace constrained {

// M(q) = Lᵀ L (ltl.hpp) in a per-thread buffer, and the dofs' parents: SINGULAR naming the body of a bad pivot.
struct Factor {
  std::vector<double> L;
  std::vector<int> lambda;
  std::int64_t of(const ModelView& mv, const double* q) {
    L.resize(static_cast<size_t>(mv.nv) * mv.nv);
    lambda.resize(static_cast<size_t>(mv.nv));
    dof_parents(mv, lambda.data());
    crba(mv, q, L.data());
    const int bad = ltl_factor(mv, lambda.data(), L.data());
    return bad >= 0 ? make_status(SINGULAR, ARG_Q, dof_body(mv, bad)) : OK;
  }
};

inline Factor& factor() {
  thread_local Factor f;
  return f;
}

// iterations −1: q̈ and λ zero (the kernels leave them unwritten)
inline void clear_if_dependent(const ModelView& mv, int m, double iterations, double* qdd, double* lam) {
  if (iterations != -1.0) return;
  std::fill(qdd, qdd + mv.nv, 0.0);
  std::fill(lam, lam + m, 0.0);
}

}  // namespace constrained

// D (m, m) = J M(q)⁻¹ Jᵀ for J (m, nv), without forming M⁻¹: M = Lᵀ L, Y = J L⁻¹, D = Y Yᵀ (ltl.hpp).
struct Delassus : Declared {
  static constexpr const char* name = "delassus";
  static constexpr Operand inputs[] = {operand::q, {"J", ARG_J, {NM, NV}, 2, false}};
  static constexpr Operand outputs[] = {operand::matrix("D", NM, NM)};
  static constexpr unsigned options = ROWS;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    constrained::Factor& f = constrained::factor();
    FD_TRY(f.of(mv, in[0]));
    thread_local std::vector<double> Y;
    delassus_from_factor(mv, f.lambda.data(), f.L.data(), in[1], opt.rows, out[0], Y);
    return OK;
  }
};

// q̈ (nv,), λ (m,), info (2,) of M q̈ + h = τ + Jᵀ λ and J q̈ = c for given rows J (m, nv), c (m,); h with gravity and
// f_ext when given. By the Schur complement on M's LᵀL factor (ltl.hpp: kkt_solve)::
//     q̈_f = M⁻¹ (τ − h),   D = J M⁻¹ Jᵀ,   (D + μ 1) λ_{k+1} = c − J q̈_f + μ λ_k,   q̈ = q̈_f + M⁻¹ Jᵀ λ
struct ConstrainedSolve : Declared {
  static constexpr const char* name = "constrained_solve";
  static constexpr Operand inputs[] = {operand::q,     operand::v, operand::tau, operand::f_ext,
                                       {"J", ARG_J, {NM, NV}, 2, false}, {"c", ARG_C, {NM}, 1, false}};
  static constexpr Operand outputs[] = {operand::vector("qdd", NV), operand::vector("lam", NM),
                                        operand::vector("info", 2)};
  static constexpr unsigned options = ROWS | SOLVER;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    constrained::Factor& f = constrained::factor();
    FD_TRY(f.of(mv, in[0]));
    thread_local std::vector<double> th;
    th.resize(static_cast<size_t>(mv.nv));
    rnea(mv, in[0], in[1], static_cast<const double*>(nullptr), in[3], true, th.data());
    for (int k = 0; k < mv.nv; ++k) th[k] = in[2][k] - th[k];
    const KktResult r = kkt_solve(mv, f.lambda.data(), f.L.data(), th.data(), in[4], in[5], opt.rows, opt.mu,
                                  opt.max_iter, opt.tol, opt.singular_tol, out[0], out[1]);
    out[2][0] = r.iterations;
    out[2][1] = r.residual;
    constrained::clear_if_dependent(mv, opt.rows, out[2][0], out[0], out[1]);
    return OK;
  }
};

// q̈ (nv,), λ (m,), info (2,) under the contacts of the call (contacts.hpp: point contacts 3 rows, frame contacts 6),
// their rows and the KKT solve in one pass::
//     point: J = the linear rows of the frame Jacobian, γ = the classical acceleration of its origin at q̈ = 0
//     frame: J = the frame Jacobian, γ = its spatial acceleration at q̈ = 0;    c = −γ − K_d J q̇
//     M q̈ + h = τ + Jᵀ λ,   J q̈ = c
struct ContactDynamics : Declared {
  static constexpr const char* name = "contact_dynamics";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::tau, operand::f_ext};
  static constexpr Operand outputs[] = {operand::vector("qdd", NV), operand::vector("lam", NM),
                                        operand::vector("info", 2)};
  static constexpr unsigned options = CONTACTS | SOLVER;
  static constexpr auto group = &fdgroup::GroupKernels::contact_dynamics;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    ContactResult<double> r;
    FD_TRY(contact_dynamics(mv, in[0], in[1], in[2], in[3], opt.contacts, opt.nc, opt.mu, opt.max_iter, opt.tol,
                            opt.singular_tol, out[0], out[1], r));
    out[2][0] = r.iterations;
    out[2][1] = r.residual;
    constrained::clear_if_dependent(mv, opt.rows, out[2][0], out[0], out[1]);
    return OK;
  }
};

// Λ (m, m) = (J M⁻¹ Jᵀ + μ 1)⁻¹ for the stacked Jacobians of the call's frames (CONTACTS: 6 rows each, m = 6k),
// J M⁻¹ Jᵀ from M's factor over the frames' chains (contacts.hpp). Status CONSTRAINT when J M⁻¹ Jᵀ + μ 1 is
// singular (a kinematic singularity with mu = 0).
struct OperationalSpaceInertia : Declared {
  static constexpr const char* name = "operational_space_inertia";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("Lambda", NM, NM)};
  static constexpr unsigned options = CONTACTS | SOLVER;
  static constexpr auto group = &fdgroup::GroupKernels::operational_space_inertia;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    return operational_space_inertia(mv, in[0], opt.contacts, opt.nc, opt.mu, opt.singular_tol, out[0]);
  }
};

// The contacts' constrained dynamics q̈ (nv,), λ (m,) at (q, q̇, τ, f_ext) (ContactDynamics) and their derivatives
// ∂q̈/∂(q, q̇, τ) (nv, nv), ∂λ/∂(q, q̇, τ) (m, nv), q along fd.integrate's tangent (contact_derivatives.hpp)::
//     ∂λ/∂x = D⁻¹ (J M⁻¹ R₁ − R₂),   ∂q̈/∂x = M⁻¹ (Jᵀ ∂λ/∂x − R₁)
// Status CONSTRAINT when the contacts are dependent or the proximal iterations did not converge (the reference
// path words them, or takes them with mu > 0).
struct ContactDynamicsDerivatives : Declared {
  static constexpr const char* name = "contact_dynamics_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::tau, operand::f_ext};
  static constexpr Operand outputs[] = {operand::matrix("ddq_dq", NV, NV),    operand::matrix("ddq_dv", NV, NV),
                                        operand::matrix("ddq_dtau", NV, NV),  operand::matrix("forces_dq", NM, NV),
                                        operand::matrix("forces_dv", NM, NV), operand::matrix("forces_dtau", NM, NV),
                                        operand::vector("qdd", NV),           operand::vector("lam", NM)};
  static constexpr unsigned options = CONTACTS | SOLVER;
  static constexpr auto group = &fdgroup::GroupKernels::contact_dynamics_derivatives_group;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    ContactResult<double> r;
    FD_TRY(contact_dynamics(mv, in[0], in[1], in[2], in[3], opt.contacts, opt.nc, opt.mu, opt.max_iter, opt.tol,
                            opt.singular_tol, out[6], out[7], r));
    if (r.iterations < 0.0) return make_status(CONSTRAINT, ARG_OUT, opt.rows);
    return group_kernels().contact_dynamics_derivatives(mv, in[0], in[1], in[3], out[6], out[7], opt.contacts,
                                                        opt.nc, opt.rows, opt.singular_tol, out);
  }
};

// An impact with the contacts (restitution e): v⁺ (nv,), Λ (m,) of M (v⁺ − v⁻) = Jᵀ Λ, J v⁺ = −e J v⁻, ContactDynamics'
// KKT solve with z = 0 and c = −(1 + e) J v⁻ (contacts.hpp). Status CONSTRAINT when the contacts are dependent (the
// reference path words it, or takes them with mu > 0). Batches in SIMD lanes on the pool.
struct ImpulseDynamics : Declared {
  static constexpr const char* name = "impulse_dynamics";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::vector("v_plus", NV), operand::vector("lam", NM)};
  static constexpr unsigned options = CONTACTS | RESTITUTION;
  static constexpr auto group = &fdgroup::GroupKernels::impulse_dynamics;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    return impulse_dynamics(mv, in[0], in[1], opt.contacts, opt.nc, opt.restitution, opt.singular_tol, out[0],
                            out[1]);
  }
};

// An impact with the contacts (restitution e): v⁺ (nv,), Λ (m,) of M (v⁺ − v⁻) = Jᵀ Λ, J v⁺ = −e J v⁻, and their
// derivatives ∂v⁺/∂(q, v⁻) (nv, nv), ∂Λ/∂(q, v⁻) (m, nv) (contact_derivatives.hpp). Status CONSTRAINT when the
// contacts are dependent (the reference path words it, or takes them with mu > 0).
struct ImpulseDynamicsDerivatives : Declared {
  static constexpr const char* name = "impulse_dynamics_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::matrix("dv_plus_dq", NV, NV), operand::matrix("dv_plus_dv", NV, NV),
                                        operand::matrix("impulses_dq", NM, NV), operand::matrix("impulses_dv", NM, NV),
                                        operand::vector("v_plus", NV),         operand::vector("lam", NM)};
  static constexpr unsigned options = CONTACTS | RESTITUTION;
  static constexpr auto group = &fdgroup::GroupKernels::impulse_dynamics_derivatives_group;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    return group_kernels().impulse_dynamics_derivatives(mv, in[0], in[1], opt.contacts, opt.nc, opt.rows,
                                                        opt.restitution, opt.singular_tol, out);
  }
};

}  // namespace fdcore

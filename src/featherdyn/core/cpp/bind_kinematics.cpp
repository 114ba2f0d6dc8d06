// The binding of the kinematics (docs/architecture.md): placements, frame placements and Jacobians, energies,
// centre of mass and centroidal momentum — one state, and rows of a batch on the pool.
#include "centroidal.hpp"
#include "energy.hpp"
#include "frames.hpp"
#include "jacobians.hpp"
#include "kinematics.hpp"
#include "simd_groups.hpp"
#include "entry_points.hpp"

namespace nb = nanobind;
using namespace fdcore;

namespace fdcore {

// H (nb, 4, 4); Hp (nb, 4, 4) when given; vel, acc (nb, 6) when v (and a) are given.
std::int64_t fk1(const ModelData& md, const F64In& q, const F64In& v, const F64In& a, const F64Out& H,
                 const F64Out& Hp, const F64Out& vel, const F64Out& acc) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  if (v.is_valid()) FD_TRY(vec(v, mv.nv, ARG_V));
  if (a.is_valid()) FD_TRY(vec(a, mv.nv, ARG_A));
  if (a.is_valid() && !v.is_valid()) return make_status(LENGTH, ARG_V, -1);
  FD_TRY(exact_shape(H, {size_t(mv.nb), 4, 4}));
  if (Hp.is_valid()) FD_TRY(exact_shape(Hp, {size_t(mv.nb), 4, 4}));
  if (v.is_valid()) FD_TRY(exact_shape(vel, {size_t(mv.nb), 6}));
  if (a.is_valid()) FD_TRY(exact_shape(acc, {size_t(mv.nb), 6}));
  for (const F64Out* o : {&H, &Hp, &vel, &acc}) FD_TRY(disjoint(*o, {{&q, ARG_Q}, {&v, ARG_V}, {&a, ARG_A}}));
  const double* vp = v.is_valid() ? v.data() : nullptr;
  const double* ap = a.is_valid() ? a.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), vp, ap, nullptr));
  forward_kinematics(mv, q.data(), vp, ap, H.data(), vp ? vel.data() : nullptr, ap ? acc.data() : nullptr,
                     Hp.is_valid() ? Hp.data() : nullptr);
  return finite_placements(H.data(), mv.nb);
}

std::int64_t frame_placement1(const ModelData& md, const F64In& q, int frame, const F64Out& pose) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  if (frame < 0 || frame >= mv.nf) return make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame);
  FD_TRY(exact_shape(pose, {4, 4}));
  FD_TRY(disjoint(pose, {{&q, ARG_Q}}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  frame_placement(mv, q.data(), frame, pose.data());
  return finite_placements(pose.data(), 1);
}

// ⁰M_f as its rotation R (3, 3) and translation p (3,): the arrays of a PluckerTransform.
std::int64_t frame_pose1(const ModelData& md, const F64In& q, int frame, const F64Out& R, const F64Out& p) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  if (frame < 0 || frame >= mv.nf) return make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame);
  FD_TRY(exact_shape(R, {3, 3}));
  FD_TRY(exact_shape(p, {3}));
  FD_TRY(disjoint(R, {{&q, ARG_Q}}));
  FD_TRY(disjoint(p, {{&q, ARG_Q}}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  Mat3<double> Rf;
  Vec3<double> pf;
  frame_pose(mv, q.data(), frame, Rf, pf);
  double* r = R.data();
  for (int k = 0; k < 9; ++k) r[k] = Rf.m[k];
  p.data()[0] = pf.x, p.data()[1] = pf.y, p.data()[2] = pf.z;
  return finite_result(p.data(), 3);  // (the rotation's entries stay within ±1: see finite_placements)
}

// H (nb, 4, 4) only: the placements of fd.compile's fk (fewer arguments to parse than fk1).
std::int64_t placements1(const ModelData& md, const F64In& q, const F64Out& H) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(H, {size_t(mv.nb), 4, 4}));
  FD_TRY(disjoint(H, {{&q, ARG_Q}}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  forward_kinematics<double>(mv, q.data(), nullptr, nullptr, H.data(), nullptr, nullptr);
  return finite_placements(H.data(), mv.nb);
}

}  // namespace fdcore

namespace {

RowStatus fk_n(const ModelData& md, const In& q, Out H) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t n = 16 * static_cast<std::int64_t>(mv.nb);
  FD_TRY_ROWS(out_rows(H, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = H.data();
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), nullptr, nullptr, nullptr); },
      [&](std::int64_t r) -> std::int64_t {
        forward_kinematics<double>(mv, Q.row(r), nullptr, nullptr, out + r * n, nullptr, nullptr);
        return OK;
      },
      group_kernels().fk, {&mv, Q, {}, {}, {}, true, out, n});
}

// Placements H, parent placements Hp (N, nb, 4, 4), velocities VEL and accelerations ACC (N, nb, 6)
// when V (and A) are given: row by row with the double instantiation, on the pool.
RowStatus kinematics_n(const ModelData& md, const In& q, const In& v, const In& a, Out H, Out Hp, Out vel,
                       Out acc) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A;
  const std::int64_t n = 16 * static_cast<std::int64_t>(mv.nb), m = 6 * static_cast<std::int64_t>(mv.nb);
  FD_TRY_ROWS(out_rows(H, n, N));
  FD_TRY_ROWS(same_rows(Hp, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  if (a.is_valid() && !v.is_valid()) return {-1, make_status(LENGTH, ARG_V, -1)};
  if (v.is_valid()) FD_TRY_ROWS(same_rows(vel, m, N));
  if (a.is_valid()) FD_TRY_ROWS(same_rows(acc, m, N));
  double *oH = H.data(), *oHp = Hp.data();
  double* oV = v.is_valid() ? vel.data() : nullptr;
  double* oA = a.is_valid() ? acc.data() : nullptr;
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), A.row(r), nullptr));
    forward_kinematics(mv, Q.row(r), V.row(r), A.row(r), oH + r * n, oV ? oV + r * m : nullptr,
                       oA ? oA + r * m : nullptr, oHp + r * n);
    return finite_placements(oH + r * n, mv.nb);
  });
}

RowStatus frame_placement_n(const ModelData& md, const In& q, int frame, Out pose) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  FD_TRY_ROWS(out_rows(pose, 16, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  if (frame < 0 || frame >= mv.nf) return {-1, make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame)};
  double* out = pose.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    frame_placement(mv, Q.row(r), frame, out + 16 * r);
    return OK;
  });
}

// ---------------------------------------------------------------------------
// whole-body quantities and Jacobians: rows of a batch (one state = one row), on the pool
// ---------------------------------------------------------------------------

// Centre of mass c (N, 3) and, with V, its velocity cd (N, 3); mass > 0 (the caller checks).
RowStatus com_n(const ModelData& md, const In& q, const In& v, double mass, Out c, Out cd) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V;
  FD_TRY_ROWS(out_rows(c, 3, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  if (v.is_valid()) FD_TRY_ROWS(same_rows(cd, 3, N));
  double* C = c.data();
  double* CD = v.is_valid() ? cd.data() : nullptr;
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), nullptr, nullptr));
    center_of_mass(mv, Q.row(r), V.row(r), mass, C + 3 * r, CD ? CD + 3 * r : nullptr);
    FD_TRY(finite_result(C + 3 * r, 3));
    return CD ? finite_result(CD + 3 * r, 3) : OK;
  });
}

// Centroidal momentum matrix A (N, 6 nv) and, with V, the momentum h (N, 6).
RowStatus centroidal_n(const ModelData& md, const In& q, const In& v, double mass, Out A, Out h) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V;
  const std::int64_t n = 6 * static_cast<std::int64_t>(mv.nv);
  FD_TRY_ROWS(out_rows(A, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  if (v.is_valid()) FD_TRY_ROWS(same_rows(h, 6, N));
  double* Ao = A.data();
  double* H = v.is_valid() ? h.data() : nullptr;
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), nullptr, nullptr));
    if (H) {
      centroidal_momentum(mv, Q.row(r), V.row(r), mass, Ao + r * n, H + 6 * r);
      FD_TRY(finite_result(H + 6 * r, 6));
    } else {
      centroidal_momentum_matrix(mv, Q.row(r), mass, Ao + r * n);
    }
    return finite_result(Ao + r * n, n);
  });
}

}  // namespace

void fdcore::bind_kinematics(nb::module_& m) {
  m.def("fk", &fk1, nb::arg("model"), arr("q"), opt("v"), opt("a"), arr("H"), opt("Hp"), opt("vel"), opt("acc"));
  m.def("frame_placement", &frame_placement1, nb::arg("model"), arr("q"), nb::arg("frame"), arr("out"));
  m.def("placements", &placements1, nb::arg("model"), arr("q"), arr("H"));
  m.def("frame_pose", &frame_pose1, nb::arg("model"), arr("q"), nb::arg("frame"), arr("R"), arr("p"));
  m.def("fk_batch", &fk_n, nb::arg("model"), arr("q"), arr("out"));
  m.def("kinematics_batch", &kinematics_n, nb::arg("model"), arr("q"), opt("v"), opt("a"), arr("H"), arr("Hp"), opt("vel"),
        opt("acc"));
  m.def("frame_placement_batch", &frame_placement_n, nb::arg("model"), arr("q"), nb::arg("frame"), arr("out"));
  m.def("com_batch", &com_n, nb::arg("model"), arr("q"), opt("v"), nb::arg("mass"), arr("c"), opt("cd"));
  m.def("centroidal_batch", &centroidal_n, nb::arg("model"), arr("q"), opt("v"), nb::arg("mass"), arr("A"), opt("h"));
}

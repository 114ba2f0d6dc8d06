// The configuration space, joint by joint (featherdyn/configuration.py, featherdyn/joints.py): integrate,
// difference and their tangent maps. Velocities are in the moving frame, [ω; v] for the free-flyer,
// [ω, v_x, v_y] for the planar joint; a quaternion is (x, y, z, w) and is moved on the group, never added to:
//
//   revolute, prismatic:  q' = q + v                         v = q1 − q0
//   spherical:            q' = q ⊗ exp(ω), normalised        ω = log(R(q0)ᵀ R(q1)),  |ω| ≤ π
//   free-flyer:           T(q') = T(q) exp([ω; v])           [ω; v] = log(T(q0)⁻¹ T(q1))
//   planar:               T(q') = T(q) exp([ω, v_x, v_y])    (SE(2))
//
// The tangent maps are block-diagonal (nv, nv), one block per joint (configuration.py's _joint_blocks):
//
//   integrate(q, v):     J_q = Ad(exp(v))⁻¹,   J_v = Jr(v)
//   difference(q0, q1):  J_1 = Jr(v)⁻¹,        J_0 = −Jr(v)⁻¹ Ad(exp(v))⁻¹      (v = difference(q0, q1))
//
// The coefficients of the exponential maps are their Taylor series below SERIES rad, where the closed forms
// lose digits (the same split as featherdyn/spatial/lie.py). Barfoot, State Estimation for Robotics, §7.1.5
// and §7.2; Solà, Deray & Atchuthan (2018), "A micro Lie theory", appendices; Pinocchio's
// algorithm/joint-configuration.hpp.
#pragma once

#include <cmath>
#include <cstddef>

#include "joints.hpp"
#include "model_view.hpp"
#include "spatial.hpp"

namespace fdcore {
namespace config {

// --- the coefficients: closed forms, Taylor series (eight terms: below 1e-17 relative at SERIES) near 0 ------------

constexpr double SERIES = 0.5;

template <std::size_t N>
inline double series(double t2, const double (&c)[N]) {
  double s = 0.0;
  for (std::size_t k = N; k-- > 0;) s = s * t2 + c[k];
  return s;
}

// sin θ / θ
inline double sinc(double t) {
  static constexpr double c[] = {1.0, -1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880, -1.0 / 39916800,
                                 1.0 / 6227020800.0, -1.0 / 1307674368000.0};
  return t >= SERIES ? std::sin(t) / t : series(t * t, c);
}
// (1 − cos θ) / θ²
inline double a1(double t) {
  static constexpr double c[] = {1.0 / 2, -1.0 / 24, 1.0 / 720, -1.0 / 40320, 1.0 / 3628800, -1.0 / 479001600,
                                 1.0 / 87178291200.0, -1.0 / 20922789888000.0};
  return t >= SERIES ? (1.0 - std::cos(t)) / (t * t) : series(t * t, c);
}
// (θ − sin θ) / θ³
inline double a2(double t) {
  static constexpr double c[] = {1.0 / 6, -1.0 / 120, 1.0 / 5040, -1.0 / 362880, 1.0 / 39916800,
                                 -1.0 / 6227020800.0, 1.0 / 1307674368000.0, -1.0 / 355687428096000.0};
  return t >= SERIES ? (t - std::sin(t)) / (t * t * t) : series(t * t, c);
}
// (θ²/2 + cos θ − 1) / θ⁴
inline double b4(double t) {
  static constexpr double c[] = {1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800, 1.0 / 479001600,
                                 -1.0 / 87178291200.0, 1.0 / 20922789888000.0, -1.0 / 6402373705728000.0};
  return t >= SERIES ? (t * t / 2 + std::cos(t) - 1.0) / (t * t * t * t) : series(t * t, c);
}
// (2θ − 3 sin θ + θ cos θ) / (2θ⁵)
inline double d5(double t) {
  static constexpr double c[] = {1.0 / 120, -1.0 / 2520, 1.0 / 120960, -1.0 / 9979200, 1.0 / 1245404160,
                                 -1.0 / 217945728000.0, 1.0 / 50812489728000.0, -1.0 / 15205637551104000.0};
  return t >= SERIES ? (2 * t - 3 * std::sin(t) + t * std::cos(t)) / (2 * t * t * t * t * t) : series(t * t, c);
}
// (1 − (θ/2) cot(θ/2)) / θ² = 1/θ² − (1 + cos θ) / (2θ sin θ): SO(3)'s Jr⁻¹ (and SE(3)'s V⁻¹), finite at θ = π
inline double e2(double t) {
  static constexpr double c[] = {1.0 / 12, 1.0 / 720, 1.0 / 30240, 1.0 / 1209600, 1.0 / 47900160,
                                 691.0 / 1307674368000.0, 1.0 / 74724249600.0, 3617.0 / 10670622842880000.0};
  if (t < SERIES) return series(t * t, c);
  const double h = t / 2;
  return (1.0 - h * std::cos(h) / std::sin(h)) / (t * t);
}

// --- SO(3) and quaternions (x, y, z, w) --------------------------------------------------------------------------

struct Quat {
  double x, y, z, w;
};

inline Quat load_quat(const double* q) { return {q[0], q[1], q[2], q[3]}; }
inline Quat conj(const Quat& a) { return {-a.x, -a.y, -a.z, a.w}; }
// a ⊗ b = (w_a u_b + w_b u_a + u_a × u_b,  w_a w_b − u_a · u_b)
inline Quat operator*(const Quat& a, const Quat& b) {
  return {a.w * b.x + b.w * a.x + a.y * b.z - a.z * b.y, a.w * b.y + b.w * a.y + a.z * b.x - a.x * b.z,
          a.w * b.z + b.w * a.z + a.x * b.y - a.y * b.x, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}
inline Quat normalized(const Quat& a) {
  const double s = 1.0 / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z + a.w * a.w);
  return {s * a.x, s * a.y, s * a.z, s * a.w};
}
// exp(ω) = (sin(θ/2) ω/θ, cos(θ/2)),  θ = |ω|
inline Quat quat_exp(const Vec3<double>& w) {
  const double t = std::sqrt(dot(w, w)), k = 0.5 * sinc(t / 2);  // sin(θ/2)/θ
  return {k * w.x, k * w.y, k * w.z, std::cos(t / 2)};
}
// log(q) = θ u/|u| with θ = 2 atan2(|u|, w) ∈ [0, π] (q and −q are the same rotation: the shorter way); the
// rotation of q/|q|
inline Vec3<double> quat_log(Quat q) {
  if (q.w < 0.0) q = {-q.x, -q.y, -q.z, -q.w};
  const double n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  const double r = n / q.w;  // (w ≥ |q|/√2 wherever r is small)
  // θ/|u| = 2 atan(r)/n = (2/w)(1 − r²/3 + r⁴/5 …)
  const double k = r < 1e-4 ? 2.0 / q.w * (1.0 - r * r / 3) : 2.0 * std::atan2(n, q.w) / n;
  return {k * q.x, k * q.y, k * q.z};
}

// exp([ω]×) = 1 + sin θ/θ [ω]× + (1 − cos θ)/θ² [ω]×²
inline Mat3<double> so3_exp(const Vec3<double>& w) {
  const double t = std::sqrt(dot(w, w));
  const Mat3<double> W = skew(w), W2 = W * W;
  Mat3<double> R = Mat3<double>::identity();
  for (int k = 0; k < 9; ++k) R.m[k] += sinc(t) * W.m[k] + a1(t) * W2.m[k];
  return R;
}
// Jr(ω) = 1 − (1 − cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×²;  V(ω) = Jr(−ω) (SE(3)'s translation of exp)
inline Mat3<double> so3_right_jacobian(const Vec3<double>& w) {
  const double t = std::sqrt(dot(w, w));
  const Mat3<double> W = skew(w), W2 = W * W;
  Mat3<double> J = Mat3<double>::identity();
  for (int k = 0; k < 9; ++k) J.m[k] += -a1(t) * W.m[k] + a2(t) * W2.m[k];
  return J;
}
// Jr(ω)⁻¹ = 1 + ½ [ω]× + e(θ) [ω]×²
inline Mat3<double> so3_right_jacobian_inverse(const Vec3<double>& w) {
  const double t = std::sqrt(dot(w, w));
  const Mat3<double> W = skew(w), W2 = W * W;
  Mat3<double> J = Mat3<double>::identity();
  for (int k = 0; k < 9; ++k) J.m[k] += 0.5 * W.m[k] + e2(t) * W2.m[k];
  return J;
}
inline Mat3<double> scaled(double s, const Mat3<double>& A) {
  Mat3<double> B;
  for (int k = 0; k < 9; ++k) B.m[k] = s * A.m[k];
  return B;
}

// Barfoot's Q(ρ, φ) (the coupling block of SE(3)'s left Jacobian; ρ translation, φ rotation):
//   Q = ½ R + a (PR + RP + PRP) + b (P²R + RP² − 3 PRP) + d (PRP² + P²RP),   P = [φ]×, R = [ρ]×
inline Mat3<double> se3_Q(const Vec3<double>& rho, const Vec3<double>& phi) {
  const double t = std::sqrt(dot(phi, phi));
  const Mat3<double> P = skew(phi), R = skew(rho);
  const Mat3<double> PR = P * R, RP = R * P, PRP = PR * P;
  const double a = a2(t), b = b4(t), d = d5(t);
  const Mat3<double> Q = scaled(0.5, R) + scaled(a, PR + RP + PRP) + scaled(b, P * PR + RP * P - scaled(3.0, PRP)) +
                         scaled(d, PRP * P + P * PRP);
  return Q;
}

// --- the blocks of the tangent maps, into an (nv, nv) row-major matrix at (i0, i0) ------------------------------

struct Block {
  double* J;
  int nv, i0;
  double& operator()(int r, int c) const { return J[static_cast<std::ptrdiff_t>(i0 + r) * nv + i0 + c]; }
  void put(int r, int c, const Mat3<double>& A) const {  // a 3 × 3 part at (r, c) of the block
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) (*this)(r + i, c + j) = A(i, j);
  }
};

// SE(3), ξ = [ω; v]:  Ad(exp(ξ))⁻¹ = [[Rᵀ, 0], [−Rᵀ [p]×, Rᵀ]] for exp(ξ) = (R, p = V(ω) v)
inline void se3_inverse_adjoint_of_exp(const Vec3<double>& w, const Vec3<double>& v, const Block& B) {
  const Mat3<double> Rt = so3_exp(w).transpose();
  const Vec3<double> p = so3_right_jacobian(-w) * v;
  B.put(0, 0, Rt);
  B.put(3, 3, Rt);
  B.put(3, 0, scaled(-1.0, Rt * skew(p)));
}
// SE(3): Jr(ξ) = [[Jr(ω), 0], [Q(−v, −ω), Jr(ω)]]
inline void se3_right_jacobian(const Vec3<double>& w, const Vec3<double>& v, const Block& B) {
  const Mat3<double> J = so3_right_jacobian(w);
  B.put(0, 0, J);
  B.put(3, 3, J);
  B.put(3, 0, se3_Q(-v, -w));
}
// SE(3): Jr(ξ)⁻¹ = [[A⁻¹, 0], [−A⁻¹ Q A⁻¹, A⁻¹]],  A = Jr(ω)
inline void se3_right_jacobian_inverse(const Vec3<double>& w, const Vec3<double>& v, const Block& B) {
  const Mat3<double> Ai = so3_right_jacobian_inverse(w);
  B.put(0, 0, Ai);
  B.put(3, 3, Ai);
  B.put(3, 0, scaled(-1.0, Ai * se3_Q(-v, -w) * Ai));
}

// SE(2), ξ = [θ, ρ1, ρ2] (angle first): Jr(ξ) = [[1, 0, 0], [d1, s, c], [d2, −c, s]] with s = sin θ/θ,
// c = (1 − cos θ)/θ, d1 = ρ1 (θ − sin θ)/θ² − ρ2 (1 − cos θ)/θ², d2 = ρ2 (θ − sin θ)/θ² + ρ1 (1 − cos θ)/θ²
// (Solà et al., eq. 163, reordered)
struct Se2Jacobian {
  double s, c, d1, d2;
  explicit Se2Jacobian(const double* xi) {
    const double th = xi[0], t = std::fabs(th);
    s = sinc(t);
    c = a1(t) * th;
    d1 = xi[1] * a2(t) * th - xi[2] * a1(t);
    d2 = xi[2] * a2(t) * th + xi[1] * a1(t);
  }
};
inline void se2_right_jacobian(const double* xi, const Block& B) {
  const Se2Jacobian j(xi);
  B(0, 0) = 1.0, B(0, 1) = 0.0, B(0, 2) = 0.0;
  B(1, 0) = j.d1, B(1, 1) = j.s, B(1, 2) = j.c;
  B(2, 0) = j.d2, B(2, 1) = -j.c, B(2, 2) = j.s;
}
// [[1, 0], [b, M]]⁻¹ = [[1, 0], [−M⁻¹ b, M⁻¹]],  M = [[s, c], [−c, s]],  M⁻¹ = [[s, −c], [c, s]] / (s² + c²)
// (s² + c² = 2 (1 − cos θ)/θ² > 0 for |θ| ≤ π)
inline void se2_right_jacobian_inverse(const double* xi, const Block& B) {
  const Se2Jacobian j(xi);
  const double k = 1.0 / (j.s * j.s + j.c * j.c);
  const double m11 = k * j.s, m12 = -k * j.c, m21 = k * j.c, m22 = k * j.s;
  B(0, 0) = 1.0, B(0, 1) = 0.0, B(0, 2) = 0.0;
  B(1, 0) = -(m11 * j.d1 + m12 * j.d2), B(1, 1) = m11, B(1, 2) = m12;
  B(2, 0) = -(m21 * j.d1 + m22 * j.d2), B(2, 1) = m21, B(2, 2) = m22;
}
// SE(2): Ad(exp(ξ))⁻¹ [ω; v] = [ω; Rᵀ (v − ω (t_y, −t_x))] for exp(ξ) = (R(θ), t), t = V ρ,
// V = [[sin θ/θ, −(1 − cos θ)/θ], [(1 − cos θ)/θ, sin θ/θ]]
inline void se2_inverse_adjoint_of_exp(const double* xi, const Block& B) {
  const double th = xi[0], t = std::fabs(th);
  const double sn = sinc(t), cn = a1(t) * th;
  const double s = sn * th, c = 1.0 - cn * th;  // sin θ, cos θ
  const double tx = sn * xi[1] - cn * xi[2], ty = cn * xi[1] + sn * xi[2];
  B(0, 0) = 1.0, B(0, 1) = 0.0, B(0, 2) = 0.0;
  B(1, 0) = -(c * ty - s * tx), B(1, 1) = c, B(1, 2) = s;
  B(2, 0) = s * ty + c * tx, B(2, 1) = -s, B(2, 2) = c;
}

// (sin θ/θ, (1 − cos θ)/θ = 2 sin²(θ/2)/θ) of the planar exponential, by two-term series below 1e-8
// (PlanarJoint.integrate; 1 − cos θ itself would lose every digit there)
inline void planar_coefficients(double w, double& a, double& b) {
  const bool small = std::fabs(w) < 1e-8;
  const double h = std::sin(w / 2);
  a = small ? 1.0 - w * w / 6 : std::sin(w) / w;
  b = small ? w / 2 - w * w * w / 24 : 2.0 * h * h / w;
}

}  // namespace config

// --- the maps of one configuration --------------------------------------------------------------------------------

// q' (nq,) = q ⊕ v (v: nv), joint by joint.
inline void integrate(const ModelView& mv, const double* q, const double* v, double* q_out) {
  using namespace config;
  for (int i = 0; i < mv.nb; ++i) {
    const double* qi = q + mv.idx_q[i];
    const double* vi = v + mv.idx_v[i];
    double* o = q_out + mv.idx_q[i];
    switch (mv.jtype[i]) {
      case SPHERICAL: {
        const Quat r = normalized(load_quat(qi) * quat_exp(load3<double>(vi)));
        o[0] = r.x, o[1] = r.y, o[2] = r.z, o[3] = r.w;
        break;
      }
      case FREE_FLYER: {  // p' = p + R(quat) V(ω) v, quat' = quat ⊗ exp(ω) in quat's hemisphere
        const Vec3<double> w = load3<double>(vi), step = so3_right_jacobian(-w) * load3<double>(vi + 3);
        const Vec3<double> p = load3<double>(qi) + quat_to_matrix(qi + 3) * step;
        const Quat q0 = load_quat(qi + 3);
        Quat r = normalized(q0 * quat_exp(w));
        if (r.x * q0.x + r.y * q0.y + r.z * q0.z + r.w * q0.w < 0.0) r = {-r.x, -r.y, -r.z, -r.w};
        o[0] = p.x, o[1] = p.y, o[2] = p.z, o[3] = r.x, o[4] = r.y, o[5] = r.z, o[6] = r.w;
        break;
      }
      case PLANAR: {  // [x, y] += Rz(θ) (a v_x − b v_y, b v_x + a v_y), θ += ω
        double a, b;
        planar_coefficients(vi[0], a, b);
        const double dx = a * vi[1] - b * vi[2], dy = b * vi[1] + a * vi[2];
        const double c = std::cos(qi[2]), s = std::sin(qi[2]);
        o[0] = qi[0] + c * dx - s * dy, o[1] = qi[1] + s * dx + c * dy, o[2] = qi[2] + vi[0];
        break;
      }
      default:  // revolute, prismatic
        o[0] = qi[0] + vi[0];
    }
  }
}

// v (nv,) with q0 ⊕ v = q1, joint by joint (rotations the shorter way).
inline void difference(const ModelView& mv, const double* q0, const double* q1, double* v) {
  using namespace config;
  for (int i = 0; i < mv.nb; ++i) {
    const double* a = q0 + mv.idx_q[i];
    const double* b = q1 + mv.idx_q[i];
    double* o = v + mv.idx_v[i];
    switch (mv.jtype[i]) {
      case SPHERICAL: {
        const Vec3<double> w = quat_log(conj(load_quat(a)) * load_quat(b));
        o[0] = w.x, o[1] = w.y, o[2] = w.z;
        break;
      }
      case FREE_FLYER: {  // ω = log(R0ᵀ R1), v = V(ω)⁻¹ R0ᵀ (p1 − p0),  V⁻¹ = 1 − ½ [ω]× + e(θ) [ω]×²
        const Vec3<double> w = quat_log(conj(load_quat(a + 3)) * load_quat(b + 3));
        const Vec3<double> p = mul_transpose(quat_to_matrix(a + 3), load3<double>(b) - load3<double>(a));
        const Vec3<double> wp = cross(w, p);
        const Vec3<double> u = p - 0.5 * wp + e2(std::sqrt(dot(w, w))) * cross(w, wp);
        o[0] = w.x, o[1] = w.y, o[2] = w.z, o[3] = u.x, o[4] = u.y, o[5] = u.z;
        break;
      }
      case PLANAR: {  // θ wrapped to (−π, π], the displacement in q0's frame through V(θ)⁻¹
        const double dth = std::atan2(std::sin(b[2] - a[2]), std::cos(b[2] - a[2]));
        const double c = std::cos(a[2]), s = std::sin(a[2]);
        const double gx = b[0] - a[0], gy = b[1] - a[1];
        const double dx = c * gx + s * gy, dy = -s * gx + c * gy;
        double p, r;
        planar_coefficients(dth, p, r);
        const double det = p * p + r * r;
        o[0] = dth, o[1] = (p * dx + r * dy) / det, o[2] = (-r * dx + p * dy) / det;
        break;
      }
      default:
        o[0] = b[0] - a[0];
    }
  }
}

// (J_q, J_v) (nv, nv) of q' = integrate(q, v): Ad(exp(v_i))⁻¹ and Jr(v_i) on each joint's diagonal block.
inline void integrate_derivatives(const ModelView& mv, const double* v, double* Jq, double* Jv) {
  using namespace config;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(mv.nv) * mv.nv; ++k) Jq[k] = Jv[k] = 0.0;
  for (int i = 0; i < mv.nb; ++i) {
    const double* xi = v + mv.idx_v[i];
    const Block A{Jq, mv.nv, mv.idx_v[i]}, B{Jv, mv.nv, mv.idx_v[i]};
    switch (mv.jtype[i]) {
      case SPHERICAL: {  // Ad(exp(ω))⁻¹ = exp(ω)ᵀ
        const Vec3<double> w = load3<double>(xi);
        A.put(0, 0, so3_exp(w).transpose());
        B.put(0, 0, so3_right_jacobian(w));
        break;
      }
      case FREE_FLYER:
        se3_inverse_adjoint_of_exp(load3<double>(xi), load3<double>(xi + 3), A);
        se3_right_jacobian(load3<double>(xi), load3<double>(xi + 3), B);
        break;
      case PLANAR:
        se2_inverse_adjoint_of_exp(xi, A);
        se2_right_jacobian(xi, B);
        break;
      default:
        A(0, 0) = B(0, 0) = 1.0;
    }
  }
}

// (J_0, J_1) (nv, nv) of v = difference(q0, q1), given that v: −Jr(v_i)⁻¹ Ad(exp(v_i))⁻¹ and Jr(v_i)⁻¹ per joint.
inline void difference_derivatives(const ModelView& mv, const double* v, double* J0, double* J1) {
  using namespace config;
  const int n = mv.nv;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(n) * n; ++k) J0[k] = J1[k] = 0.0;
  double Ad[36];
  for (int i = 0; i < mv.nb; ++i) {
    const double* xi = v + mv.idx_v[i];
    const int m = mv.nv_i[i];
    const Block B1{J1, n, mv.idx_v[i]}, A{Ad, m, 0};
    switch (mv.jtype[i]) {
      case SPHERICAL: {
        const Vec3<double> w = load3<double>(xi);
        B1.put(0, 0, so3_right_jacobian_inverse(w));
        A.put(0, 0, so3_exp(w).transpose());
        break;
      }
      case FREE_FLYER:
        for (double& x : Ad) x = 0.0;
        se3_right_jacobian_inverse(load3<double>(xi), load3<double>(xi + 3), B1);
        se3_inverse_adjoint_of_exp(load3<double>(xi), load3<double>(xi + 3), A);
        break;
      case PLANAR:
        se2_right_jacobian_inverse(xi, B1);
        se2_inverse_adjoint_of_exp(xi, A);
        break;
      default:
        B1(0, 0) = 1.0, Ad[0] = 1.0;
    }
    for (int r = 0; r < m; ++r)  // J_0 = −J_1 Ad⁻¹ on the block
      for (int c = 0; c < m; ++c) {
        double s = 0.0;
        for (int k = 0; k < m; ++k) s += B1(r, k) * Ad[k * m + c];
        J0[static_cast<std::ptrdiff_t>(mv.idx_v[i] + r) * n + mv.idx_v[i] + c] = -s;
      }
  }
}

}  // namespace fdcore

// Spatial vector algebra as small value types, templated on the scalar S.
//
// Conventions (docs/architecture.md): a motion is [ω; v], a force [n; f];
// Xform is Featherstone's plux(E, r): the transform of motion vectors from a
// frame A to a frame B whose origin sits at r (A coordinates) and whose axes
// are E (B's axes in A, as rows), RBDA §2.8 table 2.5:
//
//     X m   = [E ω;  E (v − r × ω)]
//     Xᵀ f  = [Eᵀ n + r × Eᵀ f;  Eᵀ f]          (X* maps forces B → A when transposed)
//
// A body's pose (R, p) in its parent gives X_up = plux(Rᵀ, p).
// RigidInertia holds (m, h = m c, Ī about the frame origin); ArticulatedInertia
// a symmetric 6×6 [[A, B], [Bᵀ, C]].
#pragma once

// The small operators here and in joints.hpp are forced inline: in the binding's translation unit,
// which instantiates every kernel, GCC's unit-growth limits otherwise leave them as calls that pass
// 3-vectors through memory (measured: talos forward kinematics 2.0 µs as called from Python against
// 1.05 µs for the same kernel compiled alone).
#if defined(__GNUC__) || defined(__clang__)  // (clang-cl defines no __GNUC__)
#define FD_INLINE inline __attribute__((always_inline))
#else
#define FD_INLINE inline
#endif

namespace fdcore {

template <class S>
struct Vec3 {
  S x, y, z;
};

template <class S>
FD_INLINE Vec3<S> operator+(const Vec3<S>& a, const Vec3<S>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class S>
FD_INLINE Vec3<S> operator-(const Vec3<S>& a, const Vec3<S>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class S>
FD_INLINE Vec3<S> operator-(const Vec3<S>& a) { return {-a.x, -a.y, -a.z}; }
template <class S>
FD_INLINE Vec3<S> operator*(const S& s, const Vec3<S>& a) { return {s * a.x, s * a.y, s * a.z}; }
template <class S>
FD_INLINE Vec3<S>& operator+=(Vec3<S>& a, const Vec3<S>& b) { a.x += b.x; a.y += b.y; a.z += b.z; return a; }
template <class S>
FD_INLINE Vec3<S>& operator-=(Vec3<S>& a, const Vec3<S>& b) { a.x -= b.x; a.y -= b.y; a.z -= b.z; return a; }
template <class S>
FD_INLINE S dot(const Vec3<S>& a, const Vec3<S>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class S>
FD_INLINE Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A 3×3 matrix, row-major.
template <class S>
struct Mat3 {
  S m[9];
  FD_INLINE S operator()(int r, int c) const { return m[3 * r + c]; }
  FD_INLINE S& operator()(int r, int c) { return m[3 * r + c]; }
  FD_INLINE static Mat3 identity() {
    Mat3 I;
    for (int k = 0; k < 9; ++k) I.m[k] = S(k % 4 == 0 ? 1.0 : 0.0);
    return I;
  }
  FD_INLINE Mat3 transpose() const {
    return {{m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]}};
  }
};

template <class S>
FD_INLINE Vec3<S> operator*(const Mat3<S>& R, const Vec3<S>& a) {
  return {R.m[0] * a.x + R.m[1] * a.y + R.m[2] * a.z, R.m[3] * a.x + R.m[4] * a.y + R.m[5] * a.z,
          R.m[6] * a.x + R.m[7] * a.y + R.m[8] * a.z};
}
// Rᵀ a
template <class S>
FD_INLINE Vec3<S> mul_transpose(const Mat3<S>& R, const Vec3<S>& a) {
  return {R.m[0] * a.x + R.m[3] * a.y + R.m[6] * a.z, R.m[1] * a.x + R.m[4] * a.y + R.m[7] * a.z,
          R.m[2] * a.x + R.m[5] * a.y + R.m[8] * a.z};
}
template <class S>
FD_INLINE Mat3<S> operator*(const Mat3<S>& A, const Mat3<S>& B) {
  Mat3<S> C;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) C(r, c) = A(r, 0) * B(0, c) + A(r, 1) * B(1, c) + A(r, 2) * B(2, c);
  return C;
}
template <class S>
FD_INLINE Mat3<S> operator+(const Mat3<S>& A, const Mat3<S>& B) {
  Mat3<S> C;
  for (int k = 0; k < 9; ++k) C.m[k] = A.m[k] + B.m[k];
  return C;
}
template <class S>
FD_INLINE Mat3<S> operator-(const Mat3<S>& A, const Mat3<S>& B) {
  Mat3<S> C;
  for (int k = 0; k < 9; ++k) C.m[k] = A.m[k] - B.m[k];
  return C;
}
// [a]×
template <class S>
FD_INLINE Mat3<S> skew(const Vec3<S>& a) {
  const S z(0.0);
  return {{z, -a.z, a.y, a.z, z, -a.x, -a.y, a.x, z}};
}

// Spatial motion [ω; v] and force [n; f].
template <class S>
struct Motion {
  Vec3<S> w, v;
};
template <class S>
struct Force {
  Vec3<S> n, f;
};

template <class S>
FD_INLINE Motion<S> operator+(const Motion<S>& a, const Motion<S>& b) { return {a.w + b.w, a.v + b.v}; }
template <class S>
FD_INLINE Force<S> operator+(const Force<S>& a, const Force<S>& b) { return {a.n + b.n, a.f + b.f}; }
template <class S>
FD_INLINE Force<S> operator-(const Force<S>& a, const Force<S>& b) { return {a.n - b.n, a.f - b.f}; }
template <class S>
FD_INLINE Force<S>& operator+=(Force<S>& a, const Force<S>& b) { a.n += b.n; a.f += b.f; return a; }
// the pairing m · f (power)
template <class S>
FD_INLINE S dot(const Motion<S>& m, const Force<S>& f) { return dot(m.w, f.n) + dot(m.v, f.f); }

// v × m  (crm(v) m)
template <class S>
FD_INLINE Motion<S> cross_motion(const Motion<S>& a, const Motion<S>& m) {
  return {cross(a.w, m.w), cross(a.w, m.v) + cross(a.v, m.w)};
}
// v ×* f  (crf(v) f = −crm(v)ᵀ f)
template <class S>
FD_INLINE Force<S> cross_force(const Motion<S>& a, const Force<S>& f) {
  return {cross(a.w, f.n) + cross(a.v, f.f), cross(a.w, f.f)};
}

// plux(E, r): see the file comment.
template <class S>
struct Xform {
  Mat3<S> E;
  Vec3<S> r;

  // X m
  FD_INLINE Motion<S> apply(const Motion<S>& m) const { return {E * m.w, E * (m.v - cross(r, m.w))}; }
  // X⁻¹ m
  FD_INLINE Motion<S> apply_inverse(const Motion<S>& m) const {
    const Vec3<S> w = mul_transpose(E, m.w);
    return {w, mul_transpose(E, m.v) + cross(r, w)};
  }
  // Xᵀ f
  FD_INLINE Force<S> apply_transpose(const Force<S>& f) const {
    const Vec3<S> ff = mul_transpose(E, f.f);
    return {mul_transpose(E, f.n) + cross(r, ff), ff};
  }
};

// A symmetric 3×3 matrix (xx, xy, xz, yy, yz, zz).
template <class S>
struct Sym3 {
  S xx, xy, xz, yy, yz, zz;
  FD_INLINE Mat3<S> full() const { return {{xx, xy, xz, xy, yy, yz, xz, yz, zz}}; }
  FD_INLINE static Sym3 from(const Mat3<S>& M) { return {M.m[0], M.m[1], M.m[2], M.m[4], M.m[5], M.m[8]}; }
};
template <class S>
FD_INLINE Vec3<S> operator*(const Sym3<S>& I, const Vec3<S>& a) {
  return {I.xx * a.x + I.xy * a.y + I.xz * a.z, I.xy * a.x + I.yy * a.y + I.yz * a.z,
          I.xz * a.x + I.yz * a.y + I.zz * a.z};
}
template <class S>
FD_INLINE Sym3<S> operator+(const Sym3<S>& a, const Sym3<S>& b) {
  return {a.xx + b.xx, a.xy + b.xy, a.xz + b.xz, a.yy + b.yy, a.yz + b.yz, a.zz + b.zz};
}

// A rigid body's spatial inertia about the frame origin: m, h = m c, Ī = I_c − m [c]×².
template <class S>
struct RigidInertia {
  S m;
  Vec3<S> h;
  Sym3<S> I;

  // I v = [Ī ω + h × v;  m v − h × ω]
  FD_INLINE Force<S> operator*(const Motion<S>& a) const { return {I * a.w + cross(h, a.v), m * a.v - cross(h, a.w)}; }
  FD_INLINE RigidInertia operator+(const RigidInertia& o) const { return {m + o.m, h + o.h, I + o.I}; }
};

// Xᵀ I X: a child's rigid inertia expressed in the parent (RBDA eq. 2.66 in the (m, h, Ī) form):
//     g = Eᵀ h,   h' = g + m r,   Ī' = Eᵀ Ī E − [r]× [g]× − [h']× [r]×
// and with [a]×[b]× = b aᵀ − (a·b) 1 the last two terms are symmetric rank-two updates:
//     Ī' = Eᵀ Ī E − (g rᵀ + r gᵀ) − m r rᵀ + (2 r·g + m r·r) 1
template <class S>
FD_INLINE RigidInertia<S> transform_to_parent(const Xform<S>& X, const RigidInertia<S>& I) {
  const Vec3<S> g = mul_transpose(X.E, I.h);
  const Vec3<S>& r = X.r;
  const Mat3<S> T = I.I.full() * X.E;  // Ī E; then Eᵀ (Ī E), upper triangle only
  const Mat3<S>& E = X.E;
  auto rot = [&](int a, int b) { return E(0, a) * T(0, b) + E(1, a) * T(1, b) + E(2, a) * T(2, b); };
  const S rr[3] = {r.x, r.y, r.z}, gg[3] = {g.x, g.y, g.z};
  const S diag = S(2.0) * dot(r, g) + I.m * dot(r, r);
  auto entry = [&](int a, int b) {
    S x = rot(a, b) - (gg[a] * rr[b] + rr[a] * gg[b]) - I.m * rr[a] * rr[b];
    return a == b ? x + diag : x;
  };
  return {I.m, g + I.m * r, {entry(0, 0), entry(0, 1), entry(0, 2), entry(1, 1), entry(1, 2), entry(2, 2)}};
}

// A symmetric 6×6 articulated-body inertia [[A, B], [Bᵀ, C]] (A, C symmetric).
template <class S>
struct ArticulatedInertia {
  Mat3<S> A, B, C;

  // *this = a rigid body's inertia as an articulated one, [[Ī, [h]×], [[h]×ᵀ, m 1]], written in place
  FD_INLINE void set_rigid(const RigidInertia<S>& I) {
    const S z(0.0);
    A = I.I.full();
    B = skew(I.h);
    C = Mat3<S>{{I.m, z, z, z, I.m, z, z, z, I.m}};
  }
  // *this = set_rigid(I)'s value + o, entry by entry in place (the same sums as set_rigid(I) then += o, no copy)
  FD_INLINE void set_rigid_plus(const RigidInertia<S>& I, const ArticulatedInertia& o) {
    const S z(0.0);
    A(0, 0) = I.I.xx + o.A(0, 0), A(0, 1) = I.I.xy + o.A(0, 1), A(0, 2) = I.I.xz + o.A(0, 2);
    A(1, 0) = I.I.xy + o.A(1, 0), A(1, 1) = I.I.yy + o.A(1, 1), A(1, 2) = I.I.yz + o.A(1, 2);
    A(2, 0) = I.I.xz + o.A(2, 0), A(2, 1) = I.I.yz + o.A(2, 1), A(2, 2) = I.I.zz + o.A(2, 2);
    B(0, 0) = z + o.B(0, 0), B(0, 1) = -I.h.z + o.B(0, 1), B(0, 2) = I.h.y + o.B(0, 2);
    B(1, 0) = I.h.z + o.B(1, 0), B(1, 1) = z + o.B(1, 1), B(1, 2) = -I.h.x + o.B(1, 2);
    B(2, 0) = -I.h.y + o.B(2, 0), B(2, 1) = I.h.x + o.B(2, 1), B(2, 2) = z + o.B(2, 2);
    C(0, 0) = I.m + o.C(0, 0), C(0, 1) = z + o.C(0, 1), C(0, 2) = z + o.C(0, 2);
    C(1, 0) = z + o.C(1, 0), C(1, 1) = I.m + o.C(1, 1), C(1, 2) = z + o.C(1, 2);
    C(2, 0) = z + o.C(2, 0), C(2, 1) = z + o.C(2, 1), C(2, 2) = I.m + o.C(2, 2);
  }
  FD_INLINE Force<S> operator*(const Motion<S>& a) const {
    return {A * a.w + B * a.v, mul_transpose(B, a.w) + C * a.v};
  }
  FD_INLINE ArticulatedInertia& operator+=(const ArticulatedInertia& o) {
    A = A + o.A;
    B = B + o.B;
    C = C + o.C;
    return *this;
  }
};

// Xᵀ I^a X for X = blkdiag(E, E) [[1, 0], [−[r]×, 1]]: rotate the blocks to the parent's axes
// (A' = Eᵀ A E, ...), then shift by r:  A'' = A' − B'[r]× + [r]×B'ᵀ − [r]×C'[r]×,  B'' = B' + [r]×C',  C'' = C'.
template <class S>
inline ArticulatedInertia<S> transform_to_parent(const Xform<S>& X, const ArticulatedInertia<S>& I) {
  const Mat3<S> Et = X.E.transpose();
  const Mat3<S> A = Et * I.A * X.E, B = Et * I.B * X.E, C = Et * I.C * X.E;
  const Mat3<S> rx = skew(X.r);
  const Mat3<S> Brx = B * rx;
  const Mat3<S> rxC = rx * C;
  Mat3<S> A2 = A - Brx - Brx.transpose() - rxC * rx;
  // symmetric by construction up to rounding: mirror the upper triangle
  A2(1, 0) = A2(0, 1);
  A2(2, 0) = A2(0, 2);
  A2(2, 1) = A2(1, 2);
  return {A2, B + rxC, C};
}

}  // namespace fdcore

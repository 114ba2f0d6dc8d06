// featherdyn.core._core: the nanobind binding of the compiled core (docs/architecture.md).
//
// Thin on purpose: each entry point takes native-endian, aligned, C-contiguous float64 arrays
// (no implicit conversion: nb::ndarray arguments are noconvert, and the one-state entry points
// take the buffer protocol's view with the same rules, buffer.hpp), checks their lengths, lets the
// core check finiteness and quaternions, runs one kernel, and returns a status (checks.hpp)
// that featherdyn/core/_errors.py turns into the reference's exception. No numerics here.
// The public functions' one-state path uses the *_new variants, which allocate the result and
// return it, or None where the status would not be OK (the general path then words the error).
// Batched entry points release the GIL and run rows on the core's thread pool; they return
// (row, status) of the first failing row, or (−1, 0).
#include <Python.h>
#define FEATHERDYN_NUMPY_IMPORT  // this file imports NumPy's C API (numpy_api.hpp)
#include "numpy_api.hpp"
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/complex.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include <complex>
#include <cstdint>
#include <initializer_list>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <exception>
#include <string>
#include <utility>

#include "aba.hpp"
#include "boundary.hpp"
#include "buffer.hpp"
#include "centroidal.hpp"
#include "checks.hpp"
#include "contacts.hpp"
#include "counted.hpp"
#include "crba.hpp"
#include "declarations.hpp"
#include "derivatives.hpp"
#include "energy.hpp"
#include "frame_derivatives.hpp"
#include "frames.hpp"
#include "jacobians.hpp"
#include "kinematics.hpp"
#include "ltl.hpp"
#include "model_view.hpp"
#include "pack.hpp"
#include "public_calls.hpp"
#include "regressor.hpp"
#include "rnea.hpp"
#include "simd_groups.hpp"
#include "thread_pool.hpp"

namespace nb = nanobind;
using namespace fdcore;

#if defined(FEATHERDYN_HAVE_AVX2)
fdgroup::GroupKernels featherdyn_avx2_group_kernels();    // simd_avx2.cpp
fdgroup::GroupKernels featherdyn_avx512_group_kernels();  // simd_avx512.cpp
#endif

// The batched group kernels for this CPU: AVX-512 (8 lanes) or AVX2 (4 lanes) when it has them,
// else the x86-64 baseline (2 lanes); FEATHERDYN_SIMD=baseline|avx2|avx512 asks for one (to measure
// each way; a set the CPU lacks is not taken).
const fdgroup::GroupKernels& fdcore::group_kernels() {
  static const fdgroup::GroupKernels kernels = [] {
#if defined(FEATHERDYN_HAVE_AVX2)
    const char* env = std::getenv("FEATHERDYN_SIMD");
    const std::string want = env != nullptr ? env : "";
    const bool avx512 = __builtin_cpu_supports("avx512f"), avx2 = __builtin_cpu_supports("avx2");
    if (want != "baseline" && want != "avx2" && avx512) return featherdyn_avx512_group_kernels();
    if (want != "baseline" && avx2) return featherdyn_avx2_group_kernels();
#endif
    return fdcore::group_kernels("baseline");
  }();
  return kernels;
}

namespace {

std::int64_t rnea1(const ModelData& md, const F64In& q, const F64In& v, const F64In& a, const F64In& f_ext,
                   bool gravity, const F64Out& tau) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  FD_TRY(exact_shape(tau, {size_t(mv.nv)}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), a.data(), fx));
  rnea(mv, q.data(), v.data(), a.data(), fx, gravity, tau.data());
  return finite_result(tau.data(), mv.nv);
}

std::int64_t nle1(const ModelData& md, const F64In& q, const F64In& v, const F64Out& h) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(exact_shape(h, {size_t(mv.nv)}));
  FD_TRY(check_state(mv, q.data(), v.data(), nullptr, nullptr));
  rnea<double>(mv, q.data(), v.data(), nullptr, nullptr, true, h.data());
  return finite_result(h.data(), mv.nv);
}

std::int64_t gravity1(const ModelData& md, const F64In& q, const F64Out& g) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(g, {size_t(mv.nv)}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  rnea<double>(mv, q.data(), nullptr, nullptr, nullptr, true, g.data());
  return finite_result(g.data(), mv.nv);
}

std::int64_t crba1(const ModelData& md, const F64In& q, const F64Out& M) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(M, {size_t(mv.nv), size_t(mv.nv)}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  crba(mv, q.data(), M.data());
  return finite_result(M.data(), std::int64_t(mv.nv) * mv.nv);
}

// ---------------------------------------------------------------------------
// one state, the result allocated here: the public functions' fast path
// ---------------------------------------------------------------------------

// A fresh C-contiguous float64 NumPy array (numpy_api.hpp: PyArray_SimpleNew).
nb::object numpy_alloc(std::initializer_list<npy_intp> shape) {
  PyObject* a = new_f64(static_cast<int>(shape.size()), shape.begin());
  if (a == nullptr) throw nb::python_error();
  return nb::steal(a);
}

// The element storage of an array numpy_alloc made.
inline double* array_data(const nb::object& a) { return f64_data(a.ptr()); }

// Each returns its result, or None for anything the entry point above would refuse with a status (a
// wrong length, a bad state, an overflowed or singular result): the caller's general path words it.

nb::object rnea_new(const ModelData& md, const F64In& q, const F64In& v, const F64In& a, const F64In& f_ext,
                    bool gravity) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || vec(v, mv.nv, ARG_V) != OK || vec(a, mv.nv, ARG_A) != OK) return nb::none();
  if (f_ext.is_valid() && exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT) != OK) return nb::none();
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  if (check_state(mv, q.data(), v.data(), a.data(), fx) != OK) return nb::none();
  nb::object tau = numpy_alloc({mv.nv});
  rnea(mv, q.data(), v.data(), a.data(), fx, gravity, array_data(tau));
  return finite_result(array_data(tau), mv.nv) == OK ? tau : nb::none();
}

nb::object nle_new(const ModelData& md, const F64In& q, const F64In& v) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || vec(v, mv.nv, ARG_V) != OK) return nb::none();
  if (check_state(mv, q.data(), v.data(), nullptr, nullptr) != OK) return nb::none();
  nb::object h = numpy_alloc({mv.nv});
  rnea<double>(mv, q.data(), v.data(), nullptr, nullptr, true, array_data(h));
  return finite_result(array_data(h), mv.nv) == OK ? h : nb::none();
}

nb::object gravity_new(const ModelData& md, const F64In& q) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || check_state(mv, q.data(), nullptr, nullptr, nullptr) != OK) return nb::none();
  nb::object g = numpy_alloc({mv.nv});
  rnea<double>(mv, q.data(), nullptr, nullptr, nullptr, true, array_data(g));
  return finite_result(array_data(g), mv.nv) == OK ? g : nb::none();
}

nb::object crba_new(const ModelData& md, const F64In& q) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || check_state(mv, q.data(), nullptr, nullptr, nullptr) != OK) return nb::none();
  nb::object M = numpy_alloc({mv.nv, mv.nv});
  crba(mv, q.data(), array_data(M));
  return finite_result(array_data(M), std::int64_t(mv.nv) * mv.nv) == OK ? M : nb::none();
}

nb::object aba_new(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau, const F64In& f_ext,
                   bool gravity) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || vec(v, mv.nv, ARG_V) != OK || vec(tau, mv.nv, ARG_A) != OK) return nb::none();
  if (f_ext.is_valid() && exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT) != OK) return nb::none();
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  if (check_state(mv, q.data(), v.data(), tau.data(), fx) != OK) return nb::none();
  nb::object qdd = numpy_alloc({mv.nv});
  const int bad = aba<double>(mv, q.data(), v.data(), tau.data(), fx, gravity, array_data(qdd), nullptr);
  return bad < 0 && finite_result(array_data(qdd), mv.nv) == OK ? qdd : nb::none();
}

nb::object frame_jacobian_new(const ModelData& md, const F64In& q, int frame, int ref) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || frame < 0 || frame >= mv.nf || ref < LOCAL || ref > LOCAL_WORLD_ALIGNED)
    return nb::none();
  if (check_state(mv, q.data(), nullptr, nullptr, nullptr) != OK) return nb::none();
  nb::object J = numpy_alloc({6, mv.nv});
  frame_jacobian(mv, q.data(), frame, ref, array_data(J));
  return finite_jacobian(array_data(J), mv.nv) == OK ? J : nb::none();
}

// D_singular (36,) receives the singular joint's D_i (row stride 6) when the status is SINGULAR.
std::int64_t aba1(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau, const F64In& f_ext,
                  bool gravity, const F64Out& qdd, const F64Out& D_singular) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(tau, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  FD_TRY(exact_shape(qdd, {size_t(mv.nv)}));
  if (D_singular.is_valid()) FD_TRY(exact_shape(D_singular, {36}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), tau.data(), fx));
  const int bad = aba(mv, q.data(), v.data(), tau.data(), fx, gravity, qdd.data(),
                      D_singular.is_valid() ? D_singular.data() : nullptr);
  return bad < 0 ? finite_result(qdd.data(), mv.nv) : make_status(SINGULAR, ARG_Q, bad);
}

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
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  Mat3<double> Rf;
  Vec3<double> pf;
  frame_pose(mv, q.data(), frame, Rf, pf);
  double* r = R.data();
  for (int k = 0; k < 9; ++k) r[k] = Rf.m[k];
  p.data()[0] = pf.x, p.data()[1] = pf.y, p.data()[2] = pf.z;
  return finite_result(p.data(), 3);  // (the rotation's entries stay within ±1: see finite_placements)
}

std::int64_t frame_jacobian1(const ModelData& md, const F64In& q, int frame, int ref, const F64Out& J) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  if (frame < 0 || frame >= mv.nf) return make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame);
  if (ref < LOCAL || ref > LOCAL_WORLD_ALIGNED) throw nb::value_error("reference code must be 0, 1 or 2");
  FD_TRY(exact_shape(J, {6, size_t(mv.nv)}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  frame_jacobian(mv, q.data(), frame, ref, J.data());
  return finite_jacobian(J.data(), mv.nv);
}

// RNEA on complex input (complex-step checks); no finiteness or quaternion checks.
std::int64_t rnea_complex1(const ModelData& md, const InC& q, const InC& v, const InC& a, const InC& f_ext,
                           bool gravity, OutC tau) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  require_aligned(tau);
  if (tau.size() != static_cast<size_t>(mv.nv)) return make_status(LENGTH, ARG_OUT, tau.size());
  rnea(mv, q.data(), v.data(), a.data(), f_ext.is_valid() ? f_ext.data() : nullptr, gravity, tau.data());
  return OK;
}

// ---------------------------------------------------------------------------
// batches: row r of each input (or its only row), row r of the output
// ---------------------------------------------------------------------------

RowStatus rnea_n(const ModelData& md, const In& q, const In& v, const In& a, const In& f_ext, bool gravity,
                 Out tau) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A, FX;
  FD_TRY_ROWS(out_rows(tau, mv.nv, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  const size_t nf = 6 * static_cast<size_t>(mv.nb);
  FD_TRY_ROWS(rows(f_ext, N, nf, ARG_FEXT, FX));
  double* T = tau.data();
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), A.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        rnea(mv, Q.row(r), V.row(r), A.row(r), FX.row(r), gravity, T + r * mv.nv);
        return OK;
      },
      group_kernels().rnea, {&mv, Q, V, A, FX, gravity, T, mv.nv});
}

RowStatus crba_n(const ModelData& md, const In& q, Out M) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t nv2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(M, nv2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = M.data();
  fdgroup::GroupArgs crba_args{&mv, Q, {}, {}, {}, true, out, nv2};
  crba_args.stream = fdgroup::stream_result(N, nv2);
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), nullptr, nullptr, nullptr); },
      [&](std::int64_t r) -> std::int64_t {
        crba(mv, Q.row(r), out + r * nv2);
        return OK;
      },
      group_kernels().crba, crba_args);
}

RowStatus aba_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext, bool gravity,
                Out qdd) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX;
  FD_TRY_ROWS(out_rows(qdd, mv.nv, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(tau, N, mv.nv, ARG_A, T));
  const size_t nf = 6 * static_cast<size_t>(mv.nb);
  FD_TRY_ROWS(rows(f_ext, N, nf, ARG_FEXT, FX));
  double* out = qdd.data();
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        const int bad = aba(mv, Q.row(r), V.row(r), T.row(r), FX.row(r), gravity, out + r * mv.nv);
        return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
      },
      group_kernels().aba, {&mv, Q, V, T, FX, gravity, out, mv.nv});
}

// H (nb, 4, 4) only: the placements of fd.compile's fk (fewer arguments to parse than fk1).
std::int64_t placements1(const ModelData& md, const F64In& q, const F64Out& H) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(H, {size_t(mv.nb), 4, 4}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  forward_kinematics<double>(mv, q.data(), nullptr, nullptr, H.data(), nullptr, nullptr);
  return finite_placements(H.data(), mv.nb);
}

// ---------------------------------------------------------------------------
// the public functions' one-state calls, finished in C (public_calls.hpp)
// ---------------------------------------------------------------------------

// Each fast path returns the result, or nullptr without an exception to decline: the Python
// function then takes the same arguments (and converts, computes, or words the error).
namespace pc {

PyObject* s_core = nullptr;    // "_core": a Model's CoreHandle (featherdyn/core/_model_view.py)
PyObject* s_cm = nullptr;      // CoreHandle.cm: the core's Model
PyObject* s_frames = nullptr;  // CoreHandle.frames: frame name → index

// A C++ exception in a fast path: Python's error as an exception, a refused argument as a decline.
template <class F>
PyObject* guarded(F&& body) {
  try {
    return body();
  } catch (nb::python_error& e) {
    e.restore();
  } catch (const nb::builtin_exception&) {
    // TypeError of an argument the binding does not take as it is: decline
  } catch (const std::bad_alloc&) {
    PyErr_NoMemory();
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
  }
  return nullptr;
}

// The core model and frame table of a featherdyn Model (its cached CoreHandle: extra[0] is the
// CoreHandle class); false if it has none yet (the Python function builds it) or is not a Model.
bool model_of(PublicCall* f, PyObject* model, const ModelData*& md, PyObject*& frames) {
  PyObject* h = PyObject_GetAttr(model, s_core);
  if (h == nullptr) {
    PyErr_Clear();
    return false;
  }
  if (h == f->last_handle) {
    Py_DECREF(h);
  } else {
    if (reinterpret_cast<PyObject*>(Py_TYPE(h)) != PyTuple_GET_ITEM(f->extra, 0)) {
      Py_DECREF(h);
      return false;
    }
    PyObject* cm = PyObject_GetAttr(h, s_cm);
    PyObject* fr = cm != nullptr ? PyObject_GetAttr(h, s_frames) : nullptr;
    if (fr == nullptr || !nb::isinstance<ModelData>(nb::handle(cm)) || !PyDict_CheckExact(fr)) {
      PyErr_Clear();
      Py_XDECREF(cm);
      Py_XDECREF(fr);
      Py_DECREF(h);
      return false;
    }
    Py_XSETREF(f->last_handle, h);
    Py_XSETREF(f->last_model, cm);
    Py_XSETREF(f->last_frames, fr);
  }
  md = nb::inst_ptr<ModelData>(nb::handle(f->last_model));
  frames = f->last_frames;
  return true;
}

// The same where the frame table is not needed.
bool model_of(PublicCall* f, PyObject* model, const ModelData*& md) {
  PyObject* frames = nullptr;
  return model_of(f, model, md, frames);
}

// A frame given by name (exact str) or index (exact int) within [0, nf).
bool frame_of(PyObject* frame, PyObject* frames, int nf, int& fid) {
  PyObject* index = frame;
  if (PyUnicode_CheckExact(frame)) {
    index = PyDict_GetItemWithError(frames, frame);  // borrowed
    if (index == nullptr) {
      PyErr_Clear();
      return false;
    }
  }
  if (!PyLong_CheckExact(index)) return false;
  int overflow = 0;
  const long k = PyLong_AsLongAndOverflow(index, &overflow);
  if (overflow != 0 || k < 0 || k >= nf) {
    PyErr_Clear();
    return false;
  }
  fid = static_cast<int>(k);
  return true;
}

// The reference code of `given` (absent: LOCAL) by identity with the enums at extra[at .. at + 3); false for
// anything else (a name such as "WORLD": the Python function reads it).
bool reference_of(const PublicCall* f, PyObject* given, int at, int& ref) {
  ref = LOCAL;
  if (given == nullptr) return true;
  for (const int code : {LOCAL, WORLD, LOCAL_WORLD_ALIGNED})
    if (given == PyTuple_GET_ITEM(f->extra, at + code)) {
      ref = code;
      return true;
    }
  return false;
}

// fd.frame_jacobian(model, q, frame, reference=LOCAL); extra = (CoreHandle, LOCAL, WORLD, LOCAL_WORLD_ALIGNED).
PyObject* frame_jacobian_path(PublicCall* f, PyObject* const* a) {
  const ModelData* md = nullptr;
  PyObject* frames = nullptr;
  int fid = 0, ref = LOCAL;
  if (!model_of(f, a[0], md, frames) || !frame_of(a[2], frames, md->view.nf, fid) || !reference_of(f, a[3], 1, ref))
    return nullptr;
  F64In q;
  if (!q.acquire(a[1])) return nullptr;
  return guarded([&]() -> PyObject* {
    nb::object J = frame_jacobian_new(*md, q, fid, ref);
    return J.is_none() ? nullptr : J.release().ptr();
  });
}

// R (3, 3) and p (3,), read-only, as a PluckerTransform holds them: two arrays over one 96-byte bytes object
// (one allocation, outside NumPy's memory handler; immutable, so NumPy refuses to make them writeable).
void read_only_pose(const double* R9, const double* p3, nb::object& R, nb::object& p) {
  nb::object owner = nb::steal(PyBytes_FromStringAndSize(nullptr, 12 * sizeof(double)));
  if (!owner.is_valid()) throw nb::python_error();
  char* d = PyBytes_AS_STRING(owner.ptr());
  std::memcpy(d, R9, 9 * sizeof(double));
  std::memcpy(d + 9 * sizeof(double), p3, 3 * sizeof(double));
  const npy_intp d33[2] = {3, 3}, d3[1] = {3};
  R = nb::steal(f64_view(2, d33, d, owner.ptr()));
  p = nb::steal(f64_view(1, d3, d + 9 * sizeof(double), owner.ptr()));
  if (!R.is_valid() || !p.is_valid()) throw nb::python_error();
}

// fd.frame_placement(model, q, frame) → PluckerTransform(R, p) of ⁰M_f; extra = (CoreHandle,
// PluckerTransform, and its slots' descriptors rotation, translation, source, target).
PyObject* frame_placement_path(PublicCall* f, PyObject* const* a) {
  const ModelData* md = nullptr;
  PyObject* frames = nullptr;
  int fid = 0;
  if (!model_of(f, a[0], md, frames) || !frame_of(a[2], frames, md->view.nf, fid)) return nullptr;
  F64In q;
  if (!q.acquire(a[1])) return nullptr;
  const ModelView& mv = md->view;
  if (q.ndim() != 1 || q.shape(0) != static_cast<size_t>(mv.nq)) return nullptr;
  if (check_state(mv, q.data(), nullptr, nullptr, nullptr) != OK) return nullptr;
  Mat3<double> Rf;
  Vec3<double> pf;
  frame_pose(mv, q.data(), fid, Rf, pf);
  const double p3[3] = {pf.x, pf.y, pf.z};
  if (finite_result(p3, 3) != OK) return nullptr;  // (a rotation's entries stay within ±1)
  return guarded([&]() -> PyObject* {
    nb::object R, p;
    read_only_pose(Rf.m, p3, R, p);
    // object.__new__(cls) and its four fields set as a frozen dataclass's __init__ sets them
    // (object.__setattr__: PyObject_GenericSetAttr); the names are extra[2:6] (checked by `make`)
    PyTypeObject* cls = reinterpret_cast<PyTypeObject*>(PyTuple_GET_ITEM(f->extra, 1));
    nb::object x = nb::steal(PyType_GenericNew(cls, nullptr, nullptr));
    if (!x.is_valid()) throw nb::python_error();
    PyObject* fields[4] = {R.ptr(), p.ptr(), Py_None, Py_None};
    for (int i = 0; i < 4; ++i)
      if (PyObject_GenericSetAttr(x.ptr(), PyTuple_GET_ITEM(f->extra, 2 + i), fields[i]) != 0) throw nb::python_error();
    return x.release().ptr();
  });
}

// CompiledModel.fk(q, out=None) → H (nb, 4, 4); bound = the core's Model.
PyObject* fk_path(PublicCall* f, PyObject* const* a) {
  const ModelData& md = *nb::inst_ptr<ModelData>(nb::handle(f->bound));
  F64In q;
  if (!q.acquire(a[0])) return nullptr;
  return guarded([&]() -> PyObject* {
    const bool fresh = a[1] == nullptr || a[1] == Py_None;
    nb::object H = fresh ? numpy_alloc({md.view.nb, 4, 4}) : nb::borrow(a[1]);
    F64Out h;
    if (!h.acquire(H.ptr())) return nullptr;
    return placements1(md, q, h) == OK ? H.release().ptr() : nullptr;
  });
}

// The dynamics: an array argument (absent: nullptr or None) and the gravity flag (absent: True; exactly
// True or False, anything else declines).
bool array_arg(PyObject* x, F64In& out) { return x == nullptr || x == Py_None || out.acquire(x); }
bool flag_arg(PyObject* x, bool& out) {
  out = x == nullptr || x == Py_True;
  return x == nullptr || x == Py_True || x == Py_False;
}
PyObject* result_or_decline(nb::object r) { return r.is_none() ? nullptr : r.release().ptr(); }

// fd.rnea(model, q, v, a, f_ext=None, *, gravity=True) and fd.aba(model, q, v, tau, f_ext=None, *, gravity=True)
// through rnea_new / aba_new; extra = (CoreHandle,) for the five dynamics calls
template <nb::object (*New)(const ModelData&, const F64In&, const F64In&, const F64In&, const F64In&, bool)>
PyObject* state_path(PublicCall* f, PyObject* const* a) {
  const ModelData* md = nullptr;
  F64In q, v, x, fx;
  bool g = true;
  if (!model_of(f, a[0], md) || !q.acquire(a[1]) || !v.acquire(a[2]) || !x.acquire(a[3]) ||
      !array_arg(a[4], fx) || !flag_arg(a[5], g))
    return nullptr;
  return guarded([&] { return result_or_decline(New(*md, q, v, x, fx, g)); });
}

// fd.nonlinear_effects(model, q, v)
PyObject* nle_path(PublicCall* f, PyObject* const* a) {
  const ModelData* md = nullptr;
  F64In q, v;
  if (!model_of(f, a[0], md) || !q.acquire(a[1]) || !v.acquire(a[2])) return nullptr;
  return guarded([&] { return result_or_decline(nle_new(*md, q, v)); });
}

// fd.generalized_gravity(model, q) and fd.crba(model, q) through gravity_new / crba_new
template <nb::object (*New)(const ModelData&, const F64In&)>
PyObject* configuration_path(PublicCall* f, PyObject* const* a) {
  const ModelData* md = nullptr;
  F64In q;
  if (!model_of(f, a[0], md) || !q.acquire(a[1])) return nullptr;
  return guarded([&] { return result_or_decline(New(*md, q)); });
}

// fd.compile(model)'s one-state methods, bound to the core's Model (f->bound); out= given: the out= entry
// point writes into it (status OK: out is returned), else the _new entry point allocates.
const ModelData& bound_model(const PublicCall* f) { return *nb::inst_ptr<ModelData>(nb::handle(f->bound)); }

template <class New, class Into>
PyObject* new_or_into(PyObject* out, New&& make_new, Into&& into) {
  return guarded([&]() -> PyObject* {
    if (out == nullptr || out == Py_None) return result_or_decline(make_new());
    F64Out o;
    if (!o.acquire(out)) return nullptr;
    return into(o) == OK ? Py_NewRef(out) : nullptr;
  });
}

// cm.rnea(q, v, a, f_ext=None, out=None) and cm.aba(q, v, tau, f_ext=None, out=None), with gravity
template <bool Aba>
PyObject* cm_state_path(PublicCall* f, PyObject* const* a) {
  const ModelData& md = bound_model(f);
  F64In q, v, x, fx;
  if (!q.acquire(a[0]) || !v.acquire(a[1]) || !x.acquire(a[2]) || !array_arg(a[3], fx)) return nullptr;
  if constexpr (Aba)
    return new_or_into(a[4], [&] { return aba_new(md, q, v, x, fx, true); },
                       [&](const F64Out& o) { return aba1(md, q, v, x, fx, true, o, F64Out()); });
  else
    return new_or_into(a[4], [&] { return rnea_new(md, q, v, x, fx, true); },
                       [&](const F64Out& o) { return rnea1(md, q, v, x, fx, true, o); });
}

// cm.nle(q, v, out=None)
PyObject* cm_nle_path(PublicCall* f, PyObject* const* a) {
  const ModelData& md = bound_model(f);
  F64In q, v;
  if (!q.acquire(a[0]) || !v.acquire(a[1])) return nullptr;
  return new_or_into(a[2], [&] { return nle_new(md, q, v); }, [&](const F64Out& o) { return nle1(md, q, v, o); });
}

// cm.gravity(q, out=None) and cm.crba(q, out=None)
template <nb::object (*New)(const ModelData&, const F64In&), std::int64_t (*Into)(const ModelData&, const F64In&, const F64Out&)>
PyObject* cm_configuration_path(PublicCall* f, PyObject* const* a) {
  const ModelData& md = bound_model(f);
  F64In q;
  if (!q.acquire(a[0])) return nullptr;
  return new_or_into(a[1], [&] { return New(md, q); }, [&](const F64Out& o) { return Into(md, q, o); });
}

// cm.frame_jacobian(q, frame, reference=LOCAL, out=None); extra = (frame name → index, LOCAL, WORLD, LOCAL_WORLD_ALIGNED)
PyObject* cm_frame_jacobian_path(PublicCall* f, PyObject* const* a) {
  const ModelData& md = bound_model(f);
  int fid = 0, ref = LOCAL;
  if (!frame_of(a[1], PyTuple_GET_ITEM(f->extra, 0), md.view.nf, fid) || !reference_of(f, a[2], 1, ref))
    return nullptr;
  F64In q;
  if (!q.acquire(a[0])) return nullptr;
  return new_or_into(a[3], [&] { return frame_jacobian_new(md, q, fid, ref); },
                     [&](const F64Out& o) { return frame_jacobian1(md, q, fid, ref, o); });
}

}  // namespace pc
}  // namespace

// fd.<name>(model, *inputs) of a declared algorithm (extra = (CoreHandle, its Kernel)), or fd.compile's method
// (*inputs) bound to the core's Model (extra = (its Kernel,)): Kernel.fresh's path, in C.
PyObject* fdcore::declared_path(PublicCall* f, PyObject* const* a) {
  const bool is_bound = f->bound != nullptr;
  const Kernel& k = *nb::inst_ptr<Kernel>(nb::handle(PyTuple_GET_ITEM(f->extra, is_bound ? 0 : 1)));
  const ModelData* md = nullptr;
  if (is_bound) md = &pc::bound_model(f);
  else if (!pc::model_of(f, a[0], md)) return nullptr;
  PyObject* const* in = a + (is_bound ? 0 : 1);
  return pc::guarded([&]() -> PyObject* {
    nb::tuple inputs = nb::steal<nb::tuple>(PyTuple_New(static_cast<Py_ssize_t>(k.inputs.size())));
    for (size_t i = 0; i < k.inputs.size(); ++i)
      PyTuple_SET_ITEM(inputs.ptr(), static_cast<Py_ssize_t>(i), Py_NewRef(in[i] != nullptr ? in[i] : Py_None));
    return pc::result_or_decline(run_fresh(k, *md, nb::borrow<nb::sequence>(inputs)));
  });
}

namespace {
namespace pc {

// {names}, parameters, positional, required, path; and how many constants its `extra` holds
struct NamedKind {
  const char* name;
  PublicCallKind kind;
  std::size_t constants;
};
const NamedKind KINDS[] = {
    {"frame_jacobian", {{"model", "q", "frame", "reference"}, 4, 4, 3, frame_jacobian_path}, 4},
    {"frame_placement", {{"model", "q", "frame"}, 3, 3, 3, frame_placement_path}, 6},
    {"fk", {{"q", "out"}, 2, 2, 1, fk_path}, 0},
    {"rnea", {{"model", "q", "v", "a", "f_ext", "gravity"}, 6, 5, 4, state_path<rnea_new>}, 1},
    {"aba", {{"model", "q", "v", "tau", "f_ext", "gravity"}, 6, 5, 4, state_path<aba_new>}, 1},
    {"nonlinear_effects", {{"model", "q", "v"}, 3, 3, 3, nle_path}, 1},
    {"generalized_gravity", {{"model", "q"}, 2, 2, 2, configuration_path<gravity_new>}, 1},
    {"crba", {{"model", "q"}, 2, 2, 2, configuration_path<crba_new>}, 1},
    // a compiled model's methods (bound to the core's Model)
    {"cm_rnea", {{"q", "v", "a", "f_ext", "out"}, 5, 5, 3, cm_state_path<false>}, 0},
    {"cm_aba", {{"q", "v", "tau", "f_ext", "out"}, 5, 5, 3, cm_state_path<true>}, 0},
    {"cm_nle", {{"q", "v", "out"}, 3, 3, 2, cm_nle_path}, 0},
    {"cm_gravity", {{"q", "out"}, 2, 2, 1, cm_configuration_path<gravity_new, gravity1>}, 0},
    {"cm_crba", {{"q", "out"}, 2, 2, 1, cm_configuration_path<crba_new, crba1>}, 0},
    {"cm_frame_jacobian", {{"q", "frame", "reference", "out"}, 4, 4, 2, cm_frame_jacobian_path}, 4},
};

nb::object make(const std::string& kind, nb::handle general, nb::handle extra, nb::handle bound) {
  const NamedKind* named = nullptr;
  for (const NamedKind& n : KINDS)
    if (kind == n.name) named = &n;
  if (named == nullptr) throw nb::value_error("public_call: unknown kind");
  const PublicCallKind* k = &named->kind;
  const PublicCallKind* const FK = &KINDS[2].kind;
  const PublicCallKind* const FRAME_PLACEMENT = &KINDS[1].kind;
  const std::size_t need = named->constants;
  if (!PyTuple_Check(extra.ptr()) || static_cast<std::size_t>(PyTuple_GET_SIZE(extra.ptr())) != need)
    throw nb::value_error("public_call: wrong constants for this kind");
  const bool is_bound = k == FK || kind.rfind("cm_", 0) == 0;  // a compiled model's method
  if (is_bound && !nb::isinstance<ModelData>(bound))
    throw nb::type_error("public_call: a compiled model's method needs the core's Model");
  if (kind == "cm_frame_jacobian" && !PyDict_CheckExact(PyTuple_GET_ITEM(extra.ptr(), 0)))
    throw nb::type_error("public_call: the frame table (a dict) expected");
  if (k == FRAME_PLACEMENT) {
    // the class and the names of four of its slots (data descriptors the class itself defines), which
    // frame_placement_path sets
    nb::handle cls = PyTuple_GET_ITEM(extra.ptr(), 1);
    if (!PyType_Check(cls.ptr())) throw nb::type_error("public_call: a class expected");
    for (int i = 2; i < 6; ++i) {
      nb::handle name = PyTuple_GET_ITEM(extra.ptr(), i);
      if (!PyUnicode_CheckExact(name.ptr()) || !nb::hasattr(cls, name)) throw nb::type_error("public_call: slot names expected");
      nb::object d = cls.attr(name);
      if (!PyDescr_IsData(d.ptr()) || !nb::hasattr(d, "__objclass__") || !d.attr("__objclass__").is(cls))
        throw nb::type_error("public_call: slot names expected");
    }
  }
  PyObject* r = make_public_call(k, general.ptr(), extra.ptr(), is_bound ? bound.ptr() : nullptr);
  if (r == nullptr) throw nb::python_error();
  return nb::steal(r);
}

// At import: the interned names, and the PublicCall type.
void init() {
  s_core = PyUnicode_InternFromString("_core");
  s_cm = PyUnicode_InternFromString("cm");
  s_frames = PyUnicode_InternFromString("frames");
  if (s_core == nullptr || s_cm == nullptr || s_frames == nullptr) throw nb::python_error();
  if (public_call_type() == nullptr) throw nb::python_error();
}

}  // namespace pc

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

RowStatus frame_jacobian_n(const ModelData& md, const In& q, int frame, int ref, Out J) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t n = 6 * static_cast<std::int64_t>(mv.nv);
  FD_TRY_ROWS(out_rows(J, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  if (frame < 0 || frame >= mv.nf) return {-1, make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame)};
  if (ref < LOCAL || ref > LOCAL_WORLD_ALIGNED) throw nb::value_error("reference code must be 0, 1 or 2");
  double* out = J.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    frame_jacobian(mv, Q.row(r), frame, ref, out + r * n);
    return OK;
  });
}

// ---------------------------------------------------------------------------
// whole-body quantities and Jacobians: rows of a batch (one state = one row), on the pool
// ---------------------------------------------------------------------------

// Kinetic (kind 0, needs V) or potential (kind 1) energy of every row into out (N,).
RowStatus energy_n(const ModelData& md, const In& q, const In& v, int kind, Out out) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V;
  FD_TRY_ROWS(out_rows(out, 1, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  if (kind == 0 && !v.is_valid()) return {-1, make_status(LENGTH, ARG_V, -1)};
  double* o = out.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), kind == 0 ? V.row(r) : nullptr, nullptr, nullptr));
    o[r] = kind == 0 ? kinetic_energy(mv, Q.row(r), V.row(r)) : potential_energy(mv, Q.row(r));
    return finite_result(o + r, 1);
  });
}

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

// Every joint's world columns J (N, 6 nv).
RowStatus joint_jacobians_n(const ModelData& md, const In& q, Out J) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t n = 6 * static_cast<std::int64_t>(mv.nv);
  FD_TRY_ROWS(out_rows(J, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* o = J.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    joint_jacobians(mv, Q.row(r), o + r * n);
    return finite_result(o + r * n, n);
  });
}

// J̇ of a frame (N, 6 nv) in the reference `ref` along V.
RowStatus frame_jacobian_dot_n(const ModelData& md, const In& q, const In& v, int frame, int ref, Out dJ) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V;
  const std::int64_t n = 6 * static_cast<std::int64_t>(mv.nv);
  FD_TRY_ROWS(out_rows(dJ, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  if (frame < 0 || frame >= mv.nf) return {-1, make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame)};
  if (ref < LOCAL || ref > LOCAL_WORLD_ALIGNED) throw nb::value_error("reference code must be 0, 1 or 2");
  double* o = dJ.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), nullptr, nullptr));
    frame_jacobian_time_variation(mv, Q.row(r), V.row(r), frame, ref, o + r * n);
    return finite_result(o + r * n, n);
  });
}

// The floating-point operations (+, −, ×, ÷, √) one call of a kernel does for this model and state:
// the kernel template instantiated for Counted. kind: 0 RNEA, 1 CRBA, 2 ABA (b = q̇, c = q̈ or τ).
std::int64_t flops1(const ModelData& md, int kind, const In& q, const In& v, const In& b) {
  const ModelView& mv = md.view;
  require_present(q);
  require_present(v);
  require_present(b);
  if (q.size() != size_t(mv.nq) || v.size() != size_t(mv.nv) || b.size() != size_t(mv.nv))
    throw nb::value_error("flops: q, v and the third vector must have lengths nq, nv, nv");
  std::vector<Counted> Q(q.data(), q.data() + mv.nq), V(v.data(), v.data() + mv.nv), B(b.data(), b.data() + mv.nv);
  std::vector<Counted> out(static_cast<size_t>(mv.nv) * mv.nv);
  Counted::ops() = 0;
  if (kind == 0) {
    rnea(mv, Q.data(), V.data(), B.data(), static_cast<const Counted*>(nullptr), true, out.data());
  } else if (kind == 1) {
    crba(mv, Q.data(), out.data());
  } else if (kind == 2) {
    aba(mv, Q.data(), V.data(), B.data(), static_cast<const Counted*>(nullptr), true, out.data());
  } else {
    throw nb::value_error("flops: kind must be 0 (RNEA), 1 (CRBA) or 2 (ABA)");
  }
  return Counted::ops();
}

// ---------------------------------------------------------------------------
// derivatives (derivatives.hpp): rows of a batch, on the pool
// ---------------------------------------------------------------------------

// ∂τ/∂q, ∂τ/∂q̇ (N, nv²) for rows of (q, q̇, q̈, f_ext).
RowStatus rnea_derivatives_n(const ModelData& md, const In& q, const In& v, const In& a, const In& f_ext,
                             bool gravity, Out dq, Out dv, Out M) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A, FX;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(dq, n2, N));
  FD_TRY_ROWS(same_rows(dv, n2, N));
  FD_TRY_ROWS(same_rows(M, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(a);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  FD_TRY_ROWS(rows(f_ext, N, 6 * static_cast<size_t>(mv.nb), ARG_FEXT, FX));
  double *DQ = dq.data(), *DV = dv.data(), *MM = M.data();
  fdgroup::GroupArgs args{&mv, Q, V, A, FX, gravity, DQ, n2};
  args.out2 = DV;
  args.out3 = MM;
  args.stream = fdgroup::stream_result(N, (MM ? 3 : 2) * n2);
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), A.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {  // a row alone: also the rows of a group that overflowed
        group_kernels().rnea_derivatives(mv, Q.row(r), V.row(r), A.row(r), FX.row(r), gravity, DQ + r * n2,
                                         DV + r * n2, MM + r * n2);
        FD_TRY(finite_result(DQ + r * n2, n2));  // results that finite input overflowed
        return finite_result(DV + r * n2, n2);
      },
      group_kernels().rnea_derivatives_group, args);  // (a group checks its own results while they are cached)
}

// One state (the public functions' fast path): ∂τ/∂q, ∂τ/∂q̇ (nv, nv) and ∂τ/∂q̈ = M (nv, nv), with f_ext.
std::int64_t rnea_derivatives1(const ModelData& md, const F64In& q, const F64In& v, const F64In& a,
                               const F64In& f_ext, const F64Out& dq, const F64Out& dv, const F64Out& M) {
  const ModelView& mv = md.view;
  const size_t nv = static_cast<size_t>(mv.nv);
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  for (const F64Out* o : {&dq, &dv, &M}) FD_TRY(exact_shape(*o, {nv, nv}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), a.data(), fx));
  group_kernels().rnea_derivatives(mv, q.data(), v.data(), a.data(), fx, true, dq.data(), dv.data(), M.data());
  FD_TRY(finite_result(dq.data(), static_cast<std::int64_t>(nv * nv)));
  return finite_result(dv.data(), static_cast<std::int64_t>(nv * nv));
}

// One state: ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹ (nv, nv) and q̈ (nv,), with f_ext.
std::int64_t aba_derivatives1(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau,
                              const F64In& f_ext, const F64Out& qdd, const F64Out& dq, const F64Out& dv,
                              const F64Out& Minv) {
  const ModelView& mv = md.view;
  const size_t nv = static_cast<size_t>(mv.nv);
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(tau, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  FD_TRY(exact_shape(qdd, {nv}));
  for (const F64Out* o : {&dq, &dv, &Minv}) FD_TRY(exact_shape(*o, {nv, nv}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), tau.data(), fx));
  const int* lambda = dof_tree(mv).lambda.data();
  const int bad = group_kernels().aba_derivatives(mv, lambda, q.data(), v.data(), tau.data(), fx, true,
                                                  qdd.data(), dq.data(), dv.data(), Minv.data(),
                                                  aligned_scratch(aba_derivatives_scratch(mv.nv)));
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
  FD_TRY(finite_result(dq.data(), static_cast<std::int64_t>(nv * nv)));
  return finite_result(dv.data(), static_cast<std::int64_t>(nv * nv));
}

// ∂τ/∂q, ∂τ/∂q̇ of one state by forward-mode differentiation (Dual numbers): the tests' independent check.
std::int64_t rnea_derivatives_dual1(const ModelData& md, const In& q, const In& v, const In& a, Out dq, Out dv) {
  const ModelView& mv = md.view;
  const size_t n2 = static_cast<size_t>(mv.nv) * mv.nv;
  if (q.size() != size_t(mv.nq) || v.size() != size_t(mv.nv) || a.size() != size_t(mv.nv) || dq.size() != n2 ||
      dv.size() != n2)
    return make_status(LENGTH, ARG_OUT, -1);
  FD_TRY(check_state(mv, q.data(), v.data(), a.data(), nullptr));
  rnea_derivatives_dual(mv, q.data(), v.data(), a.data(), nullptr, true, dq.data(), dv.data());
  return OK;
}

// One state: M⁻¹ (nv, nv).
std::int64_t minverse1(const ModelData& md, const F64In& q, const F64Out& Minv) {
  const ModelView& mv = md.view;
  const size_t nv = static_cast<size_t>(mv.nv);
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(Minv, {nv, nv}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  const int bad = group_kernels().minverse(mv, q.data(), Minv.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
  return finite_result(Minv.data(), static_cast<std::int64_t>(nv * nv));
}

// M⁻¹ (N, nv²) for rows of q.
RowStatus minverse_n(const ModelData& md, const In& q, Out Minv) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(Minv, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = Minv.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    const int bad = group_kernels().minverse(mv, Q.row(r), out + r * n2);
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
    return finite_result(out + r * n2, n2);
  });
}

// q̈ (N, nv), ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹ (N, nv²) for rows of (q, q̇, τ, f_ext).
RowStatus aba_derivatives_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext,
                            bool gravity, Out qdd, Out dq, Out dv, Out Minv) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(qdd, mv.nv, N));
  for (const Out* o : {&dq, &dv, &Minv}) FD_TRY_ROWS(same_rows(*o, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(tau);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(tau, N, mv.nv, ARG_A, T));
  FD_TRY_ROWS(rows(f_ext, N, 6 * static_cast<size_t>(mv.nb), ARG_FEXT, FX));
  double *QDD = qdd.data(), *DQ = dq.data(), *DV = dv.data(), *MI = Minv.data();
  std::vector<int> lambda(mv.nv);
  dof_parents(mv, lambda.data());
  fdgroup::GroupArgs args{&mv, Q, V, T, FX, gravity, DQ, n2};
  args.out2 = DV;
  args.out3 = MI;
  args.out_qdd = QDD;
  args.lambda_d = lambda.data();
  args.stream = fdgroup::stream_result(N, 3 * n2);
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        const int bad = group_kernels().aba_derivatives(mv, lambda.data(), Q.row(r), V.row(r), T.row(r), FX.row(r),
                                                        gravity, QDD + r * mv.nv, DQ + r * n2, DV + r * n2,
                                                        MI + r * n2, aligned_scratch(aba_derivatives_scratch(mv.nv)));
        if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
        FD_TRY(finite_result(DQ + r * n2, n2));  // results that finite input overflowed
        return finite_result(DV + r * n2, n2);
      },
      group_kernels().aba_derivatives_group, args);  // (a group checks its own results while they are cached)
}

// A frame's velocity derivatives (N, 6 nv) twice and, with A, its acceleration derivatives three times.
RowStatus frame_motion_derivatives_n(const ModelData& md, const In& q, const In& v, const In& a, int frame, int ref,
                                     Out dv_dq, Out dv_dv, Out da_dq, Out da_dv, Out da_da) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A;
  const std::int64_t n = 6 * static_cast<std::int64_t>(mv.nv);
  FD_TRY_ROWS(out_rows(dv_dq, n, N));
  FD_TRY_ROWS(same_rows(dv_dv, n, N));
  if (a.is_valid())
    for (const Out* o : {&da_dq, &da_dv, &da_da}) FD_TRY_ROWS(same_rows(*o, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  if (frame < 0 || frame >= mv.nf) return {-1, make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame)};
  if (ref < LOCAL || ref > LOCAL_WORLD_ALIGNED) throw nb::value_error("reference code must be 0, 1 or 2");
  const bool acc = a.is_valid();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), A.row(r), nullptr));
    frame_motion_derivatives(mv, Q.row(r), V.row(r), A.row(r), frame, ref, dv_dq.data() + r * n,
                             dv_dv.data() + r * n, acc ? da_dq.data() + r * n : nullptr,
                             acc ? da_dv.data() + r * n : nullptr, acc ? da_da.data() + r * n : nullptr);
    FD_TRY(finite_result(dv_dq.data() + r * n, n));
    return acc ? finite_result(da_dq.data() + r * n, n) : OK;
  });
}

// The joint torque regressor Y (N, nv · 10 nb) for rows of (q, q̇, q̈).
RowStatus regressor_n(const ModelData& md, const In& q, const In& v, const In& a, Out Y) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A;
  const std::int64_t n = static_cast<std::int64_t>(mv.nv) * 10 * mv.nb;
  FD_TRY_ROWS(out_rows(Y, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(a);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  double* out = Y.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), A.row(r), nullptr));
    joint_torque_regressor(mv, Q.row(r), V.row(r), A.row(r), out + r * n);
    return finite_result(out + r * n, n);
  });
}

// ---------------------------------------------------------------------------
// the tree-sparse LᵀL factorisation (ltl.hpp)
// ---------------------------------------------------------------------------

// L (N, nv²): M(q) = Lᵀ L, lower triangular (zeros above the diagonal).
RowStatus ltl_n(const ModelData& md, const In& q, Out L) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(L, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  std::vector<int> lambda(mv.nv);
  dof_parents(mv, lambda.data());
  double* out = L.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    double* Lr = out + r * n2;
    crba(mv, Q.row(r), Lr);
    const int bad = ltl_factor(mv, lambda.data(), Lr);
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    for (int i = 0; i < mv.nv; ++i)
      for (int j = i + 1; j < mv.nv; ++j) Lr[i * mv.nv + j] = 0.0;
    return finite_result(Lr, n2);
  });
}

// x (N, nv·k) solving M(q) x = b for b (N or 1, nv·k): k right-hand sides, row-major (nv, k).
RowStatus mass_solve_n(const ModelData& md, const In& q, const In& b, int k, Out x) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, B;
  const std::int64_t nk = static_cast<std::int64_t>(mv.nv) * k;
  if (k < 1) throw nb::value_error("mass_solve: k must be positive");
  FD_TRY_ROWS(out_rows(x, nk, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(b, N, nk, ARG_A, B));
  std::vector<int> lambda(mv.nv);
  dof_parents(mv, lambda.data());
  const int nv = mv.nv;
  double* out = x.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    std::vector<double> L(static_cast<size_t>(nv) * nv), col(nv);
    crba(mv, Q.row(r), L.data());
    const int bad = ltl_factor(mv, lambda.data(), L.data());
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    const double* Br = B.row(r);
    double* Xr = out + r * nk;
    for (int c = 0; c < k; ++c) {
      for (int i = 0; i < nv; ++i) col[i] = Br[i * k + c];
      ltl_solve_Lt(mv, lambda.data(), L.data(), col.data());
      ltl_solve_L(mv, lambda.data(), L.data(), col.data());
      for (int i = 0; i < nv; ++i) Xr[i * k + c] = col[i];
    }
    return finite_result(Xr, nk);
  });
}

// D (N, m²) = J M(q)⁻¹ Jᵀ for J (N or 1, m·nv).
RowStatus delassus_n(const ModelData& md, const In& q, const In& J, int m, Out D) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, JR;
  if (m < 0) throw nb::value_error("delassus: m must be non-negative");
  const int nv = mv.nv;
  FD_TRY_ROWS(out_rows(D, static_cast<size_t>(m) * m, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(J, N, static_cast<size_t>(m) * nv, ARG_A, JR));
  std::vector<int> lambda(nv);
  dof_parents(mv, lambda.data());
  double* out = D.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    std::vector<double> L(static_cast<size_t>(nv) * nv), Y;
    crba(mv, Q.row(r), L.data());
    const int bad = ltl_factor(mv, lambda.data(), L.data());
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    delassus_from_factor(mv, lambda.data(), L.data(), JR.row(r), m, out + r * m * m, Y);
    return finite_result(out + r * m * m, static_cast<std::int64_t>(m) * m);
  });
}

// The rows of a constrained-dynamics batch: outputs q̈ (N, nv), λ (N, m), info (N, 2); inputs q, v, τ, f_ext.
std::int64_t dynamics_batch_rows(const ModelView& mv, int m, const In& q, const In& v, const In& tau, const In& f_ext,
                                 const Out& qdd, const Out& lam, const Out& info, std::int64_t& N, Rows& Q, Rows& V,
                                 Rows& T, Rows& FX) {
  const int nv = mv.nv;
  FD_TRY(out_rows(qdd, nv, N));
  FD_TRY(same_rows(lam, m, N));
  FD_TRY(same_rows(info, 2, N));
  FD_TRY(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(tau);
  FD_TRY(rows(v, N, nv, ARG_V, V));
  FD_TRY(rows(tau, N, nv, ARG_A, T));
  return rows(f_ext, N, 6 * static_cast<size_t>(mv.nb), ARG_FEXT, FX);
}

// Constrained dynamics rows: q̈ (N, nv), λ (N, m), [iterations, residual] (N, 2) for M q̈ + h = τ + Jᵀλ,
// J q̈ = c with J (N or 1, m·nv) and c (N or 1, m); h with gravity and f_ext (optional).
RowStatus kkt_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext, const In& J,
                const In& c, int m, double mu, int max_iter, double tol, double singular_tol, Out qdd, Out lam,
                Out info) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX, JR, CR;
  const int nv = mv.nv;
  if (m < 0) throw nb::value_error("kkt: m must be non-negative");
  FD_TRY_ROWS(dynamics_batch_rows(mv, m, q, v, tau, f_ext, qdd, lam, info, N, Q, V, T, FX));
  FD_TRY_ROWS(rows(J, N, static_cast<size_t>(m) * nv, ARG_OUT, JR));
  FD_TRY_ROWS(rows(c, N, static_cast<size_t>(m), ARG_OUT, CR));
  std::vector<int> lambda(nv);
  dof_parents(mv, lambda.data());
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)));
    std::vector<double> L(static_cast<size_t>(nv) * nv), th(nv);
    crba(mv, Q.row(r), L.data());
    const int bad = ltl_factor(mv, lambda.data(), L.data());
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    rnea(mv, Q.row(r), V.row(r), static_cast<const double*>(nullptr), FX.row(r), true, th.data());
    for (int k = 0; k < nv; ++k) th[k] = T.row(r)[k] - th[k];
    const KktResult res = kkt_solve(mv, lambda.data(), L.data(), th.data(), JR.row(r), CR.row(r), m, mu, max_iter,
                                    tol, singular_tol, qdd.data() + r * nv, lam.data() + r * m);
    info.data()[2 * r] = res.iterations;
    info.data()[2 * r + 1] = res.residual;
    return OK;
  });
}

// Contacts given as specs (nc, 4) rows [rows (3 | 6), frame, reference code, K_d] (contacts.hpp); m = Σ rows.
std::vector<ContactSpec> contact_specs(const ModelView& mv, const double* specs, size_t nc, int& m) {
  std::vector<ContactSpec> out(nc);
  m = 0;
  for (size_t k = 0; k < nc; ++k) {
    const double* s = specs + 4 * k;
    const int rows = static_cast<int>(s[0]), frame = static_cast<int>(s[1]), ref = static_cast<int>(s[2]);
    if (!(rows == 3 || rows == 6) || !(frame >= 0 && frame < mv.nf) || !(ref >= LOCAL && ref <= LOCAL_WORLD_ALIGNED) ||
        !(s[3] >= 0.0 && s[3] < 1e300) || static_cast<double>(frame) != s[1])
      throw nb::value_error("contact specs: rows [3|6, frame index, reference code 0..2, K_d >= 0] expected");
    out[k] = ContactSpec{rows, frame, ref, s[3]};
    m += rows;
  }
  return out;
}

// The specs of one model's contacts (or frames), checked once and kept by the caller's plan cache
// (api/constraints.py), so that a one-state call converts no specs array. `model` is the ModelData it was
// checked against (its address and frame count): a call with another model is refused (TypeError: the caller's
// general path then converts).
struct ContactPlan {
  const ModelData* model;
  int nf;
  std::vector<ContactSpec> specs;
  int m = 0;
};

ContactPlan make_contact_plan(const ModelData& md, const F64In& specs) {
  require_present(specs);
  if (specs.ndim() != 2 || specs.shape(1) != 4) throw nb::value_error("contact specs: expected shape (nc, 4)");
  ContactPlan plan{&md, md.view.nf, {}, 0};
  plan.specs = contact_specs(md.view, specs.data(), specs.shape(0), plan.m);
  return plan;
}

const std::vector<ContactSpec>& plan_specs(const ModelData& md, const ContactPlan& plan) {
  if (plan.model != &md || plan.nf != md.view.nf) throw nb::type_error("contact plan: made for another model");
  return plan.specs;
}

// One state: q̈ (nv,), λ (m,), info (2,) = [iterations (−1: dependent rows, −2: not converged), residual].
std::int64_t contact_dynamics1(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau,
                               const F64In& f_ext, const ContactPlan& plan, double mu, int max_iter, double tol,
                               double singular_tol, const F64Out& qdd, const F64Out& lam, const F64Out& info) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(tau, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  const std::vector<ContactSpec>& cs = plan_specs(md, plan);
  const int m = plan.m;
  FD_TRY(exact_shape(qdd, {size_t(mv.nv)}));
  FD_TRY(exact_shape(lam, {size_t(m)}));
  FD_TRY(exact_shape(info, {2}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), tau.data(), fx));
  ContactResult<double> res;
  FD_TRY(contact_dynamics(mv, q.data(), v.data(), tau.data(), fx, cs.data(), static_cast<int>(cs.size()), mu,
                          max_iter, tol, singular_tol, qdd.data(), lam.data(), res));
  info.data()[0] = res.iterations;
  info.data()[1] = res.residual;
  return OK;
}

// Λ (6k, 6k) of k frames: specs (k, 4) rows [6, frame, reference code, 0] (contacts.hpp).
std::int64_t osi1(const ModelData& md, const F64In& q, const ContactPlan& plan, double mu, double singular_tol,
                  const F64Out& Lambda) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  const std::vector<ContactSpec>& cs = plan_specs(md, plan);
  const int m = plan.m;
  if (m != 6 * static_cast<int>(cs.size())) throw nb::value_error("frame specs: 6 rows per frame expected");
  FD_TRY(exact_shape(Lambda, {size_t(m), size_t(m)}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  if (!(mu >= 0.0)) throw nb::value_error("mu must be >= 0");
  return operational_space_inertia(mv, q.data(), cs.data(), static_cast<int>(cs.size()), mu, singular_tol,
                                   Lambda.data());
}

// Rows of a batch: q̈ (N, nv), λ (N, m), info (N, 2). Full groups of the kernels' width run contacts.hpp's
// kernel on Packs (simd_groups.hpp: contact_dynamics_group); the tail, and a group with a singular lane, row by row.
RowStatus contact_dynamics_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext,
                             const In& specs, double mu, int max_iter, double tol, double singular_tol, Out qdd,
                             Out lam, Out info) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX;
  const int nv = mv.nv;
  require_present(specs);
  if (specs.ndim() != 2 || specs.shape(1) != 4) throw nb::value_error("contact specs: expected shape (nc, 4)");
  int m = 0;
  const std::vector<ContactSpec> cs = contact_specs(mv, specs.data(), specs.shape(0), m);
  FD_TRY_ROWS(dynamics_batch_rows(mv, m, q, v, tau, f_ext, qdd, lam, info, N, Q, V, T, FX));
  const int nc = static_cast<int>(cs.size());
  const fdgroup::ContactArgs contacts{cs.data(), nc, m, mu, max_iter, tol, singular_tol, lam.data(), info.data()};
  fdgroup::GroupArgs args{&mv, Q, V, T, FX, true, qdd.data(), nv};
  args.contacts = &contacts;
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        ContactResult<double> res;
        FD_TRY(contact_dynamics(mv, Q.row(r), V.row(r), T.row(r), FX.row(r), cs.data(), nc, mu, max_iter, tol,
                                singular_tol, qdd.data() + r * nv, lam.data() + r * m, res));
        info.data()[2 * r] = res.iterations;
        info.data()[2 * r + 1] = res.residual;
        return OK;
      },
      group_kernels().contact_dynamics, args);
}

// Λ of a batch: q (N, nq) → Λ (N, m, m) for the frames of `plan` (6 rows each); full groups on Packs
// (simd_groups.hpp: operational_space_inertia_group), the tail and a group with a singular lane row by row.
RowStatus osi_n(const ModelData& md, const In& q, const ContactPlan& plan, double mu, double singular_tol,
                Out Lambda) {
  const ModelView& mv = md.view;
  const std::vector<ContactSpec>& cs = plan_specs(md, plan);
  const int m = plan.m, nc = static_cast<int>(cs.size());
  if (m != 6 * nc) throw nb::value_error("frame specs: 6 rows per frame expected");
  if (!(mu >= 0.0)) throw nb::value_error("mu must be >= 0");
  const std::int64_t m2 = static_cast<std::int64_t>(m) * m;
  std::int64_t N = 0;
  Rows Q;
  FD_TRY_ROWS(out_rows(Lambda, m2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = Lambda.data();
  const fdgroup::ContactArgs frames{cs.data(), nc, m, mu, 0, 0.0, singular_tol, nullptr, nullptr};
  fdgroup::GroupArgs args{&mv, Q, {}, {}, {}, true, out, m2};
  args.contacts = &frames;
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), nullptr, nullptr, nullptr); },
      [&](std::int64_t r) {
        return operational_space_inertia(mv, Q.row(r), cs.data(), nc, mu, singular_tol, out + r * m2);
      },
      group_kernels().operational_space_inertia, args);
}

// The core's sin and cos (trig.hpp) of every x, by the one-state path or by Packs (tests: accuracy
// against the C library, and lanes bit-identical to one state).
void sin_cos_n(const In& x, Out s, Out c, bool packs) {
  require_aligned(x);
  require_aligned(s);
  require_aligned(c);
  const size_t n = x.size();
  if (s.size() != n || c.size() != n) throw nb::value_error("sin_cos: s and c must have x's size");
  const double* X = x.data();
  double *So = s.data(), *Co = c.data();
  size_t k = 0;
  if (packs) {
    for (; k + PACK_WIDTH <= n; k += PACK_WIDTH) {
      Pack xp, sp, cp;
      for (int l = 0; l < PACK_WIDTH; ++l) xp.set(l, X[k + l]);
      sin_cos(xp, sp, cp);
      for (int l = 0; l < PACK_WIDTH; ++l) So[k + l] = sp[l], Co[k + l] = cp[l];
    }
  }
  for (; k < n; ++k) sin_cos(X[k], So[k], Co[k]);
}

// A declaration's operands as Python sees them: (name, shape with "nq", "nv", "nb" for the symbolic lengths,
// optional) each.
nb::list operands(const std::vector<Operand>& ops) {
  nb::list out;
  for (const Operand& o : ops) {
    nb::list shape;
    for (int d = 0; d < o.nd; ++d) {
      const int n = o.dims[d];
      if (n == NQ) shape.append("nq");
      else if (n == NV) shape.append("nv");
      else if (n == NB) shape.append("nb");
      else shape.append(n);
    }
    out.append(nb::make_tuple(o.name, nb::tuple(shape), o.optional));
  }
  return out;
}

ModelData* make_model(int nb, int nq, int nv, const Ints& body_ints, const In& body_reals, const In& gravity,
                      double singular_tol, double quat_tol, const Ints& frame_body, const In& frame_reals,
                      const In& armature) {
  const int nf = static_cast<int>(frame_body.size());
  const size_t n = nb < 0 ? 0 : static_cast<size_t>(nb);
  if (nb < 0 || body_ints.size() != 5 * n || body_reals.size() != BODY_REALS * n || gravity.size() != 3 ||
      frame_reals.size() != 12 * static_cast<size_t>(nf) || nv < 0 || armature.size() != static_cast<size_t>(nv))
    throw nb::value_error("featherdyn.core: inconsistent model arrays");
  return new ModelData(nb, nq, nv, nf, body_ints.data(), body_reals.data(), gravity.data(), singular_tol, quat_tol,
                       frame_body.data(), frame_reals.data(), armature.data());
}

}  // namespace

NB_MODULE(_core, m) {
  m.doc() = "featherdyn's compiled core (see featherdyn.core for the documented Python API)";
  // A core Model lives as long as its featherdyn Model (cached on it), and models held by
  // module-level caches (functools.cache, lru tables) may outlive this module at interpreter
  // exit; nanobind would report those as leaks. They are not: nothing here holds a reference.
  nb::set_leak_warnings(false);
  if (import_numpy() != 0) throw nb::python_error();  // NumPy's C API (numpy_api.hpp)
  pc::init();             // the public functions' one-state calls in C (public_calls.hpp)

  nb::class_<ModelData>(m, "Model")
      .def(nb::new_(&make_model), nb::arg("nb"), nb::arg("nq"), nb::arg("nv"), nb::arg("body_ints"),
           nb::arg("body_reals"), nb::arg("gravity"), nb::arg("singular_tol"), nb::arg("quat_tol"),
           nb::arg("frame_body"), nb::arg("frame_reals"), nb::arg("armature"))
      .def_prop_ro("nb", [](const ModelData& d) { return d.view.nb; })
      .def_prop_ro("nq", [](const ModelData& d) { return d.view.nq; })
      .def_prop_ro("nv", [](const ModelData& d) { return d.view.nv; })
      .def_prop_ro("nf", [](const ModelData& d) { return d.view.nf; });

  // every array argument: noconvert (no implicit copies or casts); optional ones accept None
  auto A = [](const char* name) { return nb::arg(name).noconvert(); };
  auto O = [](const char* name) { return nb::arg(name).noconvert().none(); };

  m.def("rnea", &rnea1, nb::arg("model"), A("q"), A("v"), A("a"), O("f_ext"), nb::arg("gravity"), A("out"));
  m.def("nle", &nle1, nb::arg("model"), A("q"), A("v"), A("out"));
  m.def("gravity", &gravity1, nb::arg("model"), A("q"), A("out"));
  m.def("crba", &crba1, nb::arg("model"), A("q"), A("out"));
  m.def("aba", &aba1, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"), nb::arg("gravity"), A("out"),
        O("D_singular"));
  m.def("fk", &fk1, nb::arg("model"), A("q"), O("v"), O("a"), A("H"), O("Hp"), O("vel"), O("acc"));
  m.def("frame_placement", &frame_placement1, nb::arg("model"), A("q"), nb::arg("frame"), A("out"));
  m.def("placements", &placements1, nb::arg("model"), A("q"), A("H"));
  m.def("frame_pose", &frame_pose1, nb::arg("model"), A("q"), nb::arg("frame"), A("R"), A("p"));
  m.def("frame_jacobian", &frame_jacobian1, nb::arg("model"), A("q"), nb::arg("frame"), nb::arg("reference"),
        A("out"));
  // the same, returning a fresh result or None (the public functions' one-state path)
  m.def("rnea_new", &rnea_new, nb::arg("model"), A("q"), A("v"), A("a"), O("f_ext"), nb::arg("gravity"));
  m.def("nle_new", &nle_new, nb::arg("model"), A("q"), A("v"));
  m.def("gravity_new", &gravity_new, nb::arg("model"), A("q"));
  m.def("crba_new", &crba_new, nb::arg("model"), A("q"));
  m.def("aba_new", &aba_new, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"), nb::arg("gravity"));
  m.def("frame_jacobian_new", &frame_jacobian_new, nb::arg("model"), A("q"), nb::arg("frame"), nb::arg("reference"));
  // a public function (or a compiled model's method) whose one-state calls run here (public_calls.hpp)
  m.def("declared_call", [](const Kernel& k, nb::handle general, nb::handle extra, nb::handle bound) {
          const bool is_bound = !bound.is_none();
          if (!PyTuple_Check(extra.ptr()) || PyTuple_GET_SIZE(extra.ptr()) != (is_bound ? 1 : 2) ||
              !nb::isinstance<Kernel>(nb::handle(PyTuple_GET_ITEM(extra.ptr(), is_bound ? 0 : 1))) ||
              nb::inst_ptr<Kernel>(nb::handle(PyTuple_GET_ITEM(extra.ptr(), is_bound ? 0 : 1))) != &k)
            throw nb::value_error("declared_call: extra must be (CoreHandle, kernel), or (kernel,) when bound");
          if (is_bound && !nb::isinstance<ModelData>(bound)) throw nb::type_error("declared_call: the core's Model expected");
          PyObject* r = make_public_call(is_bound ? &k.bound : &k.free, general.ptr(), extra.ptr(),
                                         is_bound ? bound.ptr() : nullptr);
          if (r == nullptr) throw nb::python_error();
          return nb::steal(r);
        }, nb::arg("kernel"), nb::arg("general"), nb::arg("extra"), nb::arg("bound").none(),
        "a declared algorithm's public function (or bound method) whose one-state calls run here");
  m.def("public_call", &pc::make, nb::arg("kind"), nb::arg("general"), nb::arg("extra"), nb::arg("bound").none());
  m.def("set_public_calls", [](bool on) { public_calls_enabled = on; }, nb::arg("enabled"),
        "off: every call of a public_call goes to its Python function (the default backend is 'reference')");
  m.def("rnea_complex", &rnea_complex1, nb::arg("model"), A("q"), A("v"), A("a"), O("f_ext"), nb::arg("gravity"),
        A("out"));

  m.def("rnea_batch", &rnea_n, nb::arg("model"), A("q"), A("v"), A("a"), O("f_ext"), nb::arg("gravity"), A("out"));
  m.def("crba_batch", &crba_n, nb::arg("model"), A("q"), A("out"));
  m.def("aba_batch", &aba_n, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"), nb::arg("gravity"), A("out"));
  m.def("fk_batch", &fk_n, nb::arg("model"), A("q"), A("out"));
  m.def("kinematics_batch", &kinematics_n, nb::arg("model"), A("q"), O("v"), O("a"), A("H"), A("Hp"), O("vel"),
        O("acc"));
  m.def("frame_placement_batch", &frame_placement_n, nb::arg("model"), A("q"), nb::arg("frame"), A("out"));
  m.def("frame_jacobian_batch", &frame_jacobian_n, nb::arg("model"), A("q"), nb::arg("frame"),
        nb::arg("reference"), A("out"));

  m.def("energy_batch", &energy_n, nb::arg("model"), A("q"), O("v"), nb::arg("kind"), A("out"));
  m.def("com_batch", &com_n, nb::arg("model"), A("q"), O("v"), nb::arg("mass"), A("c"), O("cd"));
  m.def("centroidal_batch", &centroidal_n, nb::arg("model"), A("q"), O("v"), nb::arg("mass"), A("A"), O("h"));
  m.def("joint_jacobians_batch", &joint_jacobians_n, nb::arg("model"), A("q"), A("out"));
  m.def("frame_jacobian_dot_batch", &frame_jacobian_dot_n, nb::arg("model"), A("q"), A("v"), nb::arg("frame"),
        nb::arg("reference"), A("out"));
  m.def("rnea_derivatives", &rnea_derivatives1, nb::arg("model"), A("q"), A("v"), A("a"), O("f_ext"),
        A("dtau_dq"), A("dtau_dv"), A("M"));
  m.def("aba_derivatives", &aba_derivatives1, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"), A("qdd"),
        A("dqdd_dq"), A("dqdd_dv"), A("Minv"));
  m.def("rnea_derivatives_batch", &rnea_derivatives_n, nb::arg("model"), A("q"), A("v"), A("a"), O("f_ext"),
        nb::arg("gravity"), A("dtau_dq"), A("dtau_dv"), A("M"));
  m.def("rnea_derivatives_dual", &rnea_derivatives_dual1, nb::arg("model"), A("q"), A("v"), A("a"), A("dtau_dq"),
        A("dtau_dv"));
  m.def("minverse_batch", &minverse_n, nb::arg("model"), A("q"), A("out"));
  m.def("mass_matrix_inverse", &minverse1, nb::arg("model"), A("q"), A("Minv"));
  m.def("aba_derivatives_batch", &aba_derivatives_n, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"),
        nb::arg("gravity"), A("qdd"), A("dqdd_dq"), A("dqdd_dv"), A("Minv"));
  m.def("frame_motion_derivatives_batch", &frame_motion_derivatives_n, nb::arg("model"), A("q"), A("v"), O("a"),
        nb::arg("frame"), nb::arg("reference"), A("dv_dq"), A("dv_dv"), O("da_dq"), O("da_dv"), O("da_da"));
  m.def("regressor_batch", &regressor_n, nb::arg("model"), A("q"), A("v"), A("a"), A("out"));
  m.def("ltl_batch", &ltl_n, nb::arg("model"), A("q"), A("out"));
  m.def("mass_solve_batch", &mass_solve_n, nb::arg("model"), A("q"), A("b"), nb::arg("k"), A("out"));
  m.def("delassus_batch", &delassus_n, nb::arg("model"), A("q"), A("J"), nb::arg("m"), A("out"));
  m.def("kkt_batch", &kkt_n, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"), A("J"), A("c"), nb::arg("m"),
        nb::arg("mu"), nb::arg("max_iter"), nb::arg("tol"), nb::arg("singular_tol"), A("qdd"), A("lam"), A("info"));
  nb::class_<ContactPlan>(m, "ContactPlan").def(nb::new_(&make_contact_plan), nb::arg("model"), A("specs"))
      .def_prop_ro("m", [](const ContactPlan& p) { return p.m; });
  m.def("contact_dynamics", &contact_dynamics1, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"), nb::arg("plan"),
        nb::arg("mu"), nb::arg("max_iter"), nb::arg("tol"), nb::arg("singular_tol"), A("qdd"), A("lam"), A("info"));
  m.def("operational_space_inertia", &osi1, nb::arg("model"), A("q"), nb::arg("plan"), nb::arg("mu"),
        nb::arg("singular_tol"), A("out"));
  m.def("operational_space_inertia_batch", &osi_n, nb::arg("model"), A("q"), nb::arg("plan"), nb::arg("mu"),
        nb::arg("singular_tol"), A("out"));
  m.def("contact_dynamics_batch", &contact_dynamics_n, nb::arg("model"), A("q"), A("v"), A("tau"), O("f_ext"),
        A("specs"), nb::arg("mu"), nb::arg("max_iter"), nb::arg("tol"), nb::arg("singular_tol"), A("qdd"), A("lam"),
        A("info"));
  // the declared algorithms (declare.hpp, declarations.hpp): each bound once, by the same three front ends
  nb::class_<Kernel>(m, "Kernel", "A declared algorithm of the core (core/cpp/declarations.hpp)")
      .def_ro("name", &Kernel::name)
      .def_prop_ro("inputs", [](const Kernel& k) { return operands(k.inputs); })
      .def_prop_ro("outputs", [](const Kernel& k) { return operands(k.outputs); })
      .def("into", &run_into, nb::arg("model"), nb::arg("inputs"), nb::arg("outputs"),
           "one state into the given outputs; the status (0: OK)")
      .def("fresh", &run_fresh, nb::arg("model"), nb::arg("inputs"),
           "one state; the result (an array or a tuple), or None where `into` would return a non-zero status")
      .def("batch", &run_batch, nb::arg("model"), nb::arg("inputs"), nb::arg("outputs"),
           "rows of a batch on the thread pool; (first failing row, status) or (-1, 0)");
  nb::dict kernels;
  for (const Kernel& k : declared_kernels()) kernels[k.name.c_str()] = nb::cast(&k, nb::rv_policy::reference);
  m.attr("kernels") = kernels;

  m.def("flops", &flops1, nb::arg("model"), nb::arg("kind"), A("q"), A("v"), A("b"),
        "floating-point operations of one RNEA (0), CRBA (1) or ABA (2) call for this state");
  m.def("sin_cos", &sin_cos_n, A("x"), A("s"), A("c"), nb::arg("packs"));
  m.def("set_num_threads", [](int n) { GlobalPool::instance().set_num_threads(n); }, nb::arg("n"));
  m.def("get_num_threads", [] { return GlobalPool::instance().num_threads(); });
  m.def("available_cores", &available_cores);
  m.def("simd", [] { return std::make_pair(std::string(group_kernels().isa), group_kernels().width); },
        "(instruction set, lanes) of the batched kernels");
}

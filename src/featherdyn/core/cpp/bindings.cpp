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

#include "boundary.hpp"
#include "build_info.hpp"
#include "entry_points.hpp"
#include "buffer.hpp"
#include "checks.hpp"
#include "cpu_features.hpp"
#include "declarations.hpp"
#include "model_view.hpp"
#include "simd_groups.hpp"
#include "thread_pool.hpp"

namespace nb = nanobind;
using namespace fdcore;

// declare.hpp's list of every declared algorithm: the one translation unit that instantiates the kernels
const std::vector<Kernel>& fdcore::declared_kernels() {
  static const std::vector<Kernel> kernels = make_declared_kernels();
  return kernels;
}

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
    const bool avx512 = cpu::features().avx512f, avx2 = cpu::features().avx2;  // cpu_features.hpp
    if (want != "baseline" && want != "avx2" && avx512) return featherdyn_avx512_group_kernels();
    if (want != "baseline" && avx2) return featherdyn_avx2_group_kernels();
#endif
    return fdcore::group_kernels("baseline");
  }();
  return kernels;
}

namespace {

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

// A declaration's operands as Python sees them: (name, shape with "nq", "nv", "nb", "np", "m" for the symbolic lengths,
// then for an input whether it is optional, for an output the name of the input it is formed with or None).
nb::list operands(const std::vector<Operand>& ops, const std::vector<Operand>* inputs = nullptr) {
  nb::list out;
  for (const Operand& o : ops) {
    nb::list shape;
    for (int d = 0; d < o.nd; ++d) {
      const int n = o.dims[d];
      if (n == NQ) shape.append("nq");
      else if (n == NV) shape.append("nv");
      else if (n == NB) shape.append("nb");
      else if (n == NP) shape.append("np");
      else if (n == NM) shape.append("m");
      else shape.append(n);
    }
    nb::object third = inputs == nullptr ? nb::object(nb::bool_(o.optional))
                       : o.when < 0     ? nb::none()
                                        : nb::object(nb::str((*inputs)[static_cast<size_t>(o.when)].name));
    out.append(nb::make_tuple(o.name, nb::tuple(shape), third));
  }
  return out;
}

// The options a declaration takes, by name.
nb::tuple option_names(unsigned options) {
  nb::list names;
  if (options & FRAME) names.append("frame");
  if (options & REFERENCE) names.append("reference");
  if (options & GRAVITY) names.append("gravity");
  if (options & ROWS) names.append("rows");
  if (options & CONTACTS) names.append("plan");
  if (options & SOLVER) names.append("solver");
  if (options & RESTITUTION) names.append("restitution");
  return nb::tuple(names);
}

// A sequence of a declaration's operands as the PyObject* the front ends take (borrowed: the sequence, a list or
// a tuple, holds them while the front end runs).
void operand_objects(const Kernel& k, const nb::sequence& xs, size_t n, PyObject** out) {
  if (nb::len(xs) != n) throw nb::value_error(("featherdyn.core." + k.name + ": wrong number of operands").c_str());
  for (size_t i = 0; i < n; ++i) out[i] = nb::handle(xs[i]).ptr();
}

std::int64_t into(const Kernel& k, const ModelData& md, const nb::sequence& inputs, const nb::sequence& outputs,
                  const CallOptions* options) {
  PyObject *ip[DECLARED_MAX], *op[DECLARED_MAX];
  operand_objects(k, inputs, k.inputs.size(), ip);
  operand_objects(k, outputs, k.outputs.size(), op);
  return run_into(k, md.view, ip, op, options_of(md, options));
}

nb::object fresh(const Kernel& k, const ModelData& md, const nb::sequence& inputs, const CallOptions* options,
                 nb::handle record) {
  if (!record.is_none() && !is_tuple_record(record.ptr()))
    throw nb::type_error(("featherdyn.core." + k.name + ": record must be None or a NamedTuple class").c_str());
  PyObject* ip[DECLARED_MAX];
  operand_objects(k, inputs, k.inputs.size(), ip);
  PyObject* outs[DECLARED_MAX];
  if (!run_fresh(k, md.view, ip, options_of(md, options), outs)) {
    if (PyErr_Occurred()) throw nb::python_error();
    return nb::none();
  }
  PyObject* r = record.is_none() ? as_result(outs, k.outputs.size())
                                 : as_tuple_record(record.ptr(), outs, k.outputs.size());
  if (r == nullptr) throw nb::python_error();
  return nb::steal(r);
}

// A SINGULAR status's detail (declare.hpp): the joint, and its D in D36, for one state of checked arrays.
std::int64_t singular_block(const Kernel& k, const ModelData& md, const nb::sequence& inputs, const F64Out& D36,
                            const CallOptions* options) {
  const Options& opt = options_of(md, options);
  if (k.singular_block == nullptr) throw nb::value_error(("featherdyn.core." + k.name + ": no singular status").c_str());
  PyObject* ip[DECLARED_MAX];
  operand_objects(k, inputs, k.inputs.size(), ip);
  std::array<F64In, DECLARED_MAX> in;
  const double* p[DECLARED_MAX] = {};
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    if (ip[i] == Py_None) continue;
    int lead = 0;
    if (!in[i].acquire(ip[i]) || declared::leading(in[i], md.view, opt, k.inputs[i], lead) != OK || lead != 0)
      throw nb::value_error("singular_block: checked float64 arrays of one state expected");
    p[i] = in[i].data();
  }
  if (!D36.is_valid() || D36.size() != 36) throw nb::value_error("singular_block: D must be a float64 array of 36");
  return k.singular_block(md.view, p, opt, D36.data());
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
  nb::class_<ModelData>(m, "Model")
      .def(nb::new_(&make_model), nb::arg("nb"), nb::arg("nq"), nb::arg("nv"), nb::arg("body_ints"),
           nb::arg("body_reals"), nb::arg("gravity"), nb::arg("singular_tol"), nb::arg("quat_tol"),
           nb::arg("frame_body"), nb::arg("frame_reals"), nb::arg("armature"))
      .def_prop_ro("nb", [](const ModelData& d) { return d.view.nb; })
      .def_prop_ro("nq", [](const ModelData& d) { return d.view.nq; })
      .def_prop_ro("nv", [](const ModelData& d) { return d.view.nv; })
      .def_prop_ro("nf", [](const ModelData& d) { return d.view.nf; });

  bind_dynamics(m);
  bind_options(m);
  bind_public_calls(m);
  bind_jax(m);

  // the declared algorithms (declare.hpp, declarations.hpp): each bound once, by the same three front ends
  nb::class_<Kernel>(m, "Kernel", "A declared algorithm of the core (core/cpp/declarations.hpp)")
      .def_ro("name", &Kernel::name)
      .def_prop_ro("inputs", [](const Kernel& k) { return operands(k.inputs); })
      .def_prop_ro("outputs", [](const Kernel& k) { return operands(k.outputs, &k.inputs); })
      .def_prop_ro("options", [](const Kernel& k) { return option_names(k.options); })
      .def_prop_ro("parameters", [](const Kernel& k) {  // fd.<name>'s, in order (declare.hpp: Slots)
        nb::list names;
        for (int i = 0; i < k.free.nparams; ++i) names.append(k.free.names[i]);
        return nb::tuple(names);
      })
      .def("into", &into, nb::arg("model"), nb::arg("inputs"), nb::arg("outputs"), nb::arg("options").none() = nb::none(),
           "one state, or a stack of them (inputs of the declared shapes under the same leading lengths, or one "
           "state's), into the given outputs (options: an Options or None); the status (0: OK; -1: an argument not "
           "taken as it is)")
      .def("fresh", &fresh, nb::arg("model"), nb::arg("inputs"), nb::arg("options").none() = nb::none(),
           nb::arg("record").none() = nb::none(),
           "one state, or a stack of them (as `into`); the result (an array, a tuple, or the record: a NamedTuple "
           "class the outputs make, in order), or None where `into` would return a non-zero status")
      .def("singular_block", &singular_block, nb::arg("model"), nb::arg("inputs"), nb::arg("D"), nb::arg("options").none() = nb::none(),
           "the joint a SINGULAR status names (-1: none) for one checked state, its D written into D (36,)")
      .def("batch", [](const Kernel& k, const ModelData& md, const nb::sequence& inputs, const nb::sequence& outputs,
                       const CallOptions* options) {
             return run_batch(k, md.view, inputs, outputs, options_of(md, options));
           }, nb::arg("model"), nb::arg("inputs"), nb::arg("outputs"), nb::arg("options").none() = nb::none(),
           "rows of a batch on the thread pool; (first failing row, status) or (-1, 0)");
  nb::dict kernels;
  for (const Kernel& k : declared_kernels()) kernels[k.name.c_str()] = nb::cast(&k, nb::rv_policy::reference);
  m.attr("kernels") = kernels;

  m.def("set_result_allocator", [](nb::object fn, std::int64_t min_bytes) {
    Py_XSETREF(result_allocator.fn, fn.release().ptr());  // numpy_api.hpp: a one-state result's large arrays
    result_allocator.min_bytes = static_cast<npy_intp>(min_bytes);
  }, nb::arg("fn"), nb::arg("min_bytes"), "fn(shape) gives the memory of a one-state result of min_bytes or more");
  m.def("sin_cos", &sin_cos_n, arr("x"), arr("s"), arr("c"), nb::arg("packs"));
  m.def("set_num_threads", [](int n) { GlobalPool::instance().set_num_threads(n); }, nb::arg("n"));
  m.def("get_num_threads", [] { return GlobalPool::instance().num_threads(); });
  m.def("available_cores", &available_cores);
  m.def("simd", [] { return std::make_pair(std::string(group_kernels().isa), group_kernels().width); },
        "(instruction set, lanes) of the batched kernels");
  bind_build_info(m);  // build_info.cpp
}

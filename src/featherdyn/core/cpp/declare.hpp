// Declared algorithms (docs/architecture.md, "One declaration per algorithm"): an algorithm states its name,
// its operands with symbolic shapes and its kernel on one state, once; the templates here make every front
// end of the binding from that — the one-state call into given arrays (`into`), the one-state call that
// allocates its results (`fresh`) and the batch on the thread pool (`batch`) — and `Kernel` carries the
// declaration to Python, where the public function, `out=`, Dask and `fd.compile`'s method are made from it
// (featherdyn/api/declared.py).
//
// A declaration D is a struct deriving from `Declared` with
//     static constexpr const char* name;
//     static constexpr Operand inputs[] = {...}, outputs[] = {...};
//     static std::int64_t run(const ModelView&, const double* const* in, double* const* out, const Options&);
// and, where it has them, `options` (GRAVITY | FRAME | REFERENCE | ROWS | CONTACTS | SOLVER: the parameters it
// takes besides its arrays) and `group`
// (its SIMD kernel of one group of rows, simd_groups.hpp: the batch then runs in lanes). `run` gets each input
// (nullptr for an absent optional one) and each output, all of the declared shapes and already checked
// (lengths, finiteness, unit quaternions, the frame's index), and returns OK or its own status (checks.hpp:
// SINGULAR naming the joint); the front ends then check the outputs for overflow (NONFINITE).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "boundary.hpp"
#include "contact_spec.hpp"
#include "groups.hpp"
#include "public_calls.hpp"

namespace fdcore {

// A symbolic length: the model's nq, nv or nb, np = 10 nb (the bodies' dynamic parameters), or the call's m (the
// constraint rows: Options::rows); a non-negative value is a literal length.
enum SymbolicLength : int { NQ = -1, NV = -2, NB = -3, NP = -4, NM = -5 };

// An input or output: its name, the status argument that names it in an error (checks.hpp: ARG_Q for q, ARG_V,
// ARG_A for q̈ or τ, ARG_FEXT, ARG_Q1 for a second configuration, ARG_POINT, ARG_OUT), its shape (up to three lengths),
// whether an input may be absent, for an output formed only when an optional input is given, that input's index
// (`when`; −1: always formed), and whether an input comes after the options in the public calls' parameters
// (`after_options`: a point follows the frame it is in, fd.kinematics_derivatives(model, q, v, a, frame, reference,
// point)).
struct Operand {
  const char* name;
  std::int64_t arg;
  int dims[3];
  int nd;
  bool optional;
  int when = -1;
  bool after_options = false;
};

// The operands the declarations share: the state (q, q̇, q̈ or τ, and optional body-frame forces), two
// configurations (q0 checked as q is, q1 as a second one: fd.difference's), and results of one number, a vector or a
// matrix of symbolic lengths.
namespace operand {
constexpr Operand q{"q", ARG_Q, {NQ}, 1, false}, v{"v", ARG_V, {NV}, 1, false}, a{"a", ARG_A, {NV}, 1, false},
    tau{"tau", ARG_A, {NV}, 1, false}, f_ext{"f_ext", ARG_FEXT, {NB, 6}, 2, true};
constexpr Operand q0{"q0", ARG_Q, {NQ}, 1, false}, q1{"q1", ARG_Q1, {NQ}, 1, false};
constexpr Operand w{"w", ARG_W, {NV}, 1, false};  // a cotangent of a result of length nv (fd.rnea_vjp's)
constexpr Operand W{"W", ARG_W, {NV, NV}, 2, false};  // a cotangent of an (nv, nv) result (fd.crba_vjp's)
// an optional point (3) in the frame's coordinates, after the frame and reference options
constexpr Operand point{"point", ARG_POINT, {3}, 1, true, -1, true};
constexpr Operand scalar(const char* name) { return {name, ARG_OUT, {}, 0, false}; }
constexpr Operand vector(const char* name, int n) { return {name, ARG_OUT, {n}, 1, false}; }
constexpr Operand matrix(const char* name, int rows, int cols) { return {name, ARG_OUT, {rows, cols}, 2, false}; }
constexpr Operand placements(const char* name) { return {name, ARG_OUT, {NB, 4, 4}, 3, false}; }  // (nb, 4, 4)
// an optional input, and an output formed only when input `input` is given
constexpr Operand optional(Operand o) { return o.optional = true, o; }
constexpr Operand when_given(Operand o, int input) { return o.when = input, o; }
}  // namespace operand

// The parameters a declaration may take besides its arrays: the gravity flag (gravity=True), a frame (its index),
// a reference (0 LOCAL, 1 WORLD, 2 LOCAL_WORLD_ALIGNED: frames.hpp), the constraint rows m (ROWS: the length NM),
// contacts (CONTACTS: their specs, contact_spec.hpp, which also fix m) and the KKT solver's settings (SOLVER: the
// proximal weight mu ≥ 0, its iterations and tolerance, and the pivot below which D = J M⁻¹ Jᵀ is singular).
enum OptionBits : unsigned { GRAVITY = 1u, FRAME = 2u, REFERENCE = 4u, ROWS = 8u, CONTACTS = 16u, SOLVER = 32u,
                             RESTITUTION = 64u };
struct Options {
  bool gravity = true;
  int frame = 0;
  int reference = 0;
  int rows = 0;
  const ContactSpec* contacts = nullptr;
  int nc = 0;
  double mu = 0.0;
  int max_iter = 50;
  double tol = 1e-12;
  double singular_tol = 0.0;
  double restitution = 0.0;  // an impact's coefficient e ∈ [0, 1]
};

// What a declaration's status means beyond its code, for the error's words: ABA's SINGULAR names the joint, and
// `singular_block` gives that joint's D = Sᵀ Iᴬ S (6 × 6, row stride 6) whose smallest eigenvalue the error states.
using SingularBlockFn = std::int64_t (*)(const ModelView&, const double* const* in, const struct Options&, double* D36);

// What a declaration does not state: no options, no SIMD kernel, no detail of its status, outputs scanned for
// overflow by run_checked. `checks_outputs`: the kernel returns NONFINITE for an overflowed output itself (when it
// can vouch for its outputs more cheaply than a scan of them: rnea_second_derivatives' mostly-zero tensors).
struct Declared {
  static constexpr unsigned options = 0;
  static constexpr fdgroup::GroupFn fdgroup::GroupKernels::*group = nullptr;
  static constexpr SingularBlockFn singular_block = nullptr;
  static constexpr bool checks_outputs = false;
};

constexpr int DECLARED_MAX = 8;  // inputs, and outputs, of one declaration at most

// The status of an argument a front end does not take as it is (not an exact native float64 array): not the
// user's mistake — the caller converts it (the Python path), or declines (the public call in C).
constexpr std::int64_t NOT_TAKEN = -1;

inline std::int64_t length_of(const ModelView& mv, const Options& opt, int d) {
  return d == NQ ? mv.nq : d == NV ? mv.nv : d == NB ? mv.nb : d == NP ? 10 * std::int64_t{mv.nb} : d == NM ? opt.rows : d;
}
inline std::int64_t size_of(const ModelView& mv, const Options& opt, const Operand& o) {
  std::int64_t n = 1;
  for (int k = 0; k < o.nd; ++k) n *= length_of(mv, opt, o.dims[k]);
  return n;
}

// Where a public call's parameters are (its kind's names, in order; -1: not a parameter): fd.<name>'s are
// (model, *inputs, [frame, reference], *inputs after the options, *, [gravity], out), fd.compile's method's
// (*inputs, [frame, reference], *inputs after the options, out, *, [gravity]). `input[i]`: input i's.
struct Slots {
  int input[DECLARED_MAX], frame, reference, gravity, out;
};

// A declaration with its type erased: what the binding and Python see. `free` and `bound` are its public
// calls' parameters (public_calls.hpp), `free_at` and `bound_at` where each one is.
struct Kernel {
  std::string name;
  std::vector<Operand> inputs, outputs;
  std::int64_t (*run)(const ModelView&, const double* const* in, double* const* out, const Options&);
  unsigned options = 0;
  fdgroup::GroupFn fdgroup::GroupKernels::*group = nullptr;
  SingularBlockFn singular_block = nullptr;
  bool checks_outputs = false;
  PublicCallKind free{}, bound{};
  Slots free_at{}, bound_at{};
};

PyObject* declared_path(PublicCall* f, PyObject* const* args);  // (bind_public_calls.cpp)

namespace declared {

// A public call's parameters (Slots): fd.<name>'s with the model first, fd.compile's method's without it.
inline void parameters(const Kernel& k, bool with_model, PublicCallKind& kind, Slots& at) {
  int n = 0, required = 0;
  auto add = [&](const char* name, bool needed) {
    kind.names[n] = name;
    if (needed) required = n + 1;
    return n++;
  };
  if (with_model) add("model", true);
  for (size_t i = 0; i < k.inputs.size(); ++i)
    if (!k.inputs[i].after_options) at.input[i] = add(k.inputs[i].name, !k.inputs[i].optional);
  at.frame = k.options & FRAME ? add("frame", true) : -1;
  at.reference = k.options & REFERENCE ? add("reference", false) : -1;
  for (size_t i = 0; i < k.inputs.size(); ++i)
    if (k.inputs[i].after_options) at.input[i] = add(k.inputs[i].name, !k.inputs[i].optional);
  kind.positional = n;
  if (!with_model) kind.positional = (at.out = add("out", false)) + 1;
  at.gravity = k.options & GRAVITY ? add("gravity", false) : -1;
  if (with_model) at.out = add("out", false);
  kind.nparams = n;
  kind.required = required;
  kind.path = &declared_path;
}

}  // namespace declared

template <class D>
Kernel declare() {
  static_assert(std::size(D::inputs) <= DECLARED_MAX && std::size(D::outputs) <= DECLARED_MAX);
  static_assert(2 + std::size(D::inputs) + !!(D::options & FRAME) + !!(D::options & REFERENCE) +
                    !!(D::options & GRAVITY) <= PUBLIC_CALL_MAX_ARGS);  // model, inputs, the options, out
  Kernel k{D::name, std::vector<Operand>(std::begin(D::inputs), std::end(D::inputs)),
           std::vector<Operand>(std::begin(D::outputs), std::end(D::outputs)), &D::run, D::options, D::group,
           D::singular_block, D::checks_outputs};
  declared::parameters(k, true, k.free, k.free_at);
  declared::parameters(k, false, k.bound, k.bound_at);
  return k;
}

namespace declared {

// The state check of the inputs (finiteness, unit quaternions): by the status argument each one names; a second
// configuration (ARG_Q1), a cotangent (ARG_W, finite) and a point (ARG_POINT, finite) after the state.
inline std::int64_t check_inputs(const Kernel& k, const ModelView& mv, const double* const* in) {
  const double* by_arg[4] = {nullptr, nullptr, nullptr, nullptr};  // q, v, a or τ, f_ext
  const double *q1 = nullptr, *w = nullptr, *point = nullptr;
  std::int64_t w_size = 0;
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    if (k.inputs[i].arg <= ARG_FEXT) by_arg[k.inputs[i].arg] = in[i];
    if (k.inputs[i].arg == ARG_Q1) q1 = in[i];
    if (k.inputs[i].arg == ARG_W) w = in[i], w_size = size_of(mv, Options{}, k.inputs[i]);
    if (k.inputs[i].arg == ARG_POINT) point = in[i];
  }
  FD_TRY(check_state(mv, by_arg[0], by_arg[1], by_arg[2], by_arg[3]));
  if (w != nullptr && !all_finite(w, w_size)) return make_status(NONFINITE, ARG_W, first_nonfinite(w, w_size));
  if (point != nullptr && !all_finite(point, 3)) return make_status(NONFINITE, ARG_POINT, first_nonfinite(point, 3));
  return q1 != nullptr ? check_configuration(mv, q1, ARG_Q1) : OK;
}

// The options' values: a frame index within [0, nf) (a LENGTH status naming the frame), a reference 0, 1 or 2.
inline std::int64_t check_options(const Kernel& k, const ModelView& mv, const Options& opt) {
  if ((k.options & FRAME) && (opt.frame < 0 || opt.frame >= mv.nf))
    return make_status(LENGTH, ARG_FRAME, opt.frame < 0 ? 0 : opt.frame);
  if ((k.options & REFERENCE) && (opt.reference < 0 || opt.reference > 2)) return NOT_TAKEN;
  if ((k.options & (ROWS | CONTACTS)) && opt.rows < 0) return NOT_TAKEN;
  if ((k.options & SOLVER) && !(opt.mu >= 0.0 && opt.mu < 1e300 && opt.max_iter >= 1 && opt.tol > 0.0 && opt.tol < 1e300))
    return NOT_TAKEN;  // (the Python path words the error)
  if ((k.options & RESTITUTION) && !(opt.restitution >= 0.0 && opt.restitution <= 1.0)) return NOT_TAKEN;
  return OK;
}

// The overflow check of a state's outputs (the no declared operands, nullptr where not formed): NONFINITE naming
// the first non-finite entry, or OK.
inline std::int64_t finite_outputs(const ModelView& mv, const Options& opt, const Operand* outputs, size_t no,
                                   double* const* out) {
  for (size_t o = 0; o < no; ++o)
    if (out[o] != nullptr) FD_TRY(finite_result(out[o], size_of(mv, opt, outputs[o])));
  return OK;
}

// Run the kernel on one checked state and check its outputs for overflow (unless the kernel does).
inline std::int64_t run_checked(const Kernel& k, const ModelView& mv, const double* const* in, double* const* out,
                                const Options& opt) {
  FD_TRY(check_inputs(k, mv, in));
  FD_TRY(k.run(mv, in, out, opt));
  return k.checks_outputs ? OK : finite_outputs(mv, opt, k.outputs.data(), k.outputs.size(), out);
}

// The states a public call's arrays hold as they are: one (every input exactly its declared shape), or a stack of
// N = ∏ dims of them (an input its declared shape under the leading lengths `dims`, the same for every input that
// has leading lengths; an input of exactly its declared shape is read by every state). At most STACK_MAX_DIMS
// leading lengths; more, or inputs with different ones (broadcasting), go to the Python path.
constexpr int STACK_MAX_DIMS = 8;
struct Stack {
  int nd = 0;  // 0: one state
  std::int64_t dims[STACK_MAX_DIMS] = {};
  std::int64_t N = 1;
};

// An operand of a public call as it is: its declared shape under `lead` ≥ 0 leading lengths (OK), or a LENGTH status
// naming it (its declared part wrong).
template <class A>
std::int64_t leading(const A& x, const ModelView& mv, const Options& opt, const Operand& o, int& lead) {
  lead = static_cast<int>(x.ndim()) - o.nd;
  bool same = lead >= 0;
  for (int d = 0; same && d < o.nd; ++d)
    same = static_cast<std::int64_t>(x.shape(static_cast<size_t>(lead + d))) == length_of(mv, opt, o.dims[d]);
  return same ? OK : make_status(LENGTH, o.arg, x.ndim() == 1 ? static_cast<std::int64_t>(x.shape(0)) : -1);
}

// Whether an operand's `lead` leading lengths are the stack's.
template <class A>
bool on_stack(const A& x, int lead, const Stack& s) {
  bool same = lead == s.nd;
  for (int d = 0; same && d < lead; ++d) same = static_cast<std::int64_t>(x.shape(static_cast<size_t>(d))) == s.dims[d];
  return same;
}

// A public call's inputs as they are (take): each one's memory as rows (stride 0: one state, read by every row;
// p nullptr where absent), and the stack of states they make.
struct Taken {
  std::array<F64In, DECLARED_MAX> in;
  std::array<Rows, DECLARED_MAX> rows{};
  Stack stack;
};

// Take the inputs (nullptr or None where absent) and check the options: OK, NOT_TAKEN, or the status of the first
// failure (a required input absent, a wrong length, an option's value).
inline std::int64_t take(const Kernel& k, const ModelView& mv, PyObject* const* inputs, const Options& opt, Taken& t) {
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    PyObject* x = inputs[i];
    if (x == nullptr || x == Py_None) {
      if (!k.inputs[i].optional) return make_status(LENGTH, k.inputs[i].arg, -1);
      continue;
    }
    if (!t.in[i].acquire(x)) return NOT_TAKEN;
    int lead = 0;
    FD_TRY(leading(t.in[i], mv, opt, k.inputs[i], lead));
    if (lead > 0 && t.stack.nd == 0) {  // the first input with leading lengths sets the stack's
      if (lead > STACK_MAX_DIMS) return NOT_TAKEN;
      t.stack.nd = lead;
      for (int d = 0; d < lead; ++d) t.stack.N *= t.stack.dims[d] = static_cast<std::int64_t>(t.in[i].shape(static_cast<size_t>(d)));
    } else if (lead > 0 && !on_stack(t.in[i], lead, t.stack)) {
      return NOT_TAKEN;  // other leading lengths (broadcasting: the Python path's)
    }
    t.rows[i] = Rows{t.in[i].data(), lead == 0 ? 0 : size_of(mv, opt, k.inputs[i])};
  }
  return check_options(k, mv, opt);
}

// Run taken inputs into outputs of the stack's shapes (op, n_out: each output's numbers a state; nullptr where not
// formed): one state by run_checked, a stack by run_rows, the one batch path (the thread pool, SIMD groups). OK, or
// the first failure's status (a stack's first failing row's).
inline std::int64_t run_taken(const Kernel& k, const ModelView& mv, const Taken& t, double* const* op,
                              const std::int64_t* n_out, const Options& opt);

// Whether output o is formed: always, or when the input it depends on is given (`given(i)`).
template <class Given>
bool formed(const Kernel& k, size_t o, Given&& given) {
  return k.outputs[o].when < 0 || given(static_cast<size_t>(k.outputs[o].when));
}
inline bool absent(PyObject* x) { return x == nullptr || x == Py_None; }

}  // namespace declared

// One state, or a stack of them (declared::Stack), into given outputs of the declared shapes under the stack's
// leading lengths: OK, NOT_TAKEN (an array not taken as it is; an empty stack), or the status of the first failure
// (declared::take; an output's wrong length; outputs that share memory with each other: OVERLAP on ARG_OUT; an output
// over an input: OVERLAP on the input, which the Python path's one rule takes; run_taken).
inline std::int64_t run_into(const Kernel& k, const ModelView& mv, PyObject* const* inputs, PyObject* const* outputs,
                             const Options& opt) {
  declared::Taken t;
  FD_TRY(declared::take(k, mv, inputs, opt, t));
  if (t.stack.N == 0) return NOT_TAKEN;
  std::array<F64Out, DECLARED_MAX> out;
  std::array<double*, DECLARED_MAX> op{};
  std::array<std::int64_t, DECLARED_MAX> n{};
  for (size_t o = 0; o < k.outputs.size(); ++o) {
    if (!declared::formed(k, o, [&](size_t i) { return !declared::absent(inputs[i]); })) {
      if (!declared::absent(outputs[o])) return NOT_TAKEN;  // an array for an output not formed: the Python path
      continue;
    }
    if (!out[o].acquire(outputs[o])) return NOT_TAKEN;
    int lead = 0;
    FD_TRY(declared::leading(out[o], mv, opt, k.outputs[o], lead));
    if (!declared::on_stack(out[o], lead, t.stack)) return make_status(LENGTH, ARG_OUT, -1);
    op[o] = out[o].data();
    n[o] = size_of(mv, opt, k.outputs[o]);
    for (size_t p = 0; p < o; ++p)
      if (overlaps(op[o], t.stack.N * n[o], op[p], t.stack.N * n[p])) return make_status(OVERLAP, ARG_OUT, 0);
    for (size_t i = 0; i < k.inputs.size(); ++i)
      if (t.rows[i].p != nullptr && overlaps(op[o], t.stack.N * n[o], t.rows[i].p, static_cast<std::int64_t>(t.in[i].size())))
        return make_status(OVERLAP, k.inputs[i].arg, 0);
  }
  return declared::run_taken(k, mv, t, op.data(), n.data(), opt);
}

// One state, or a stack of them, the outputs allocated here (None where not formed): true with a new reference in
// each outs[o], or false with none — an exception set if allocating failed, else for anything run_into would not
// return OK for (the caller then declines: the Python path converts or words it). `read_only`: the outputs
// read-only, as a record holds them (one state's as views of one block of memory: a bytes object, one allocation
// outside NumPy's memory handler; a stack's from result_f64, whose large arrays are reused memory).
inline bool run_fresh(const Kernel& k, const ModelView& mv, PyObject* const* inputs, const Options& opt,
                      PyObject** outs, bool read_only = false) {
  declared::Taken t;
  if (declared::take(k, mv, inputs, opt, t) != OK || t.stack.N == 0) return false;
  const declared::Stack& s = t.stack;
  std::array<double*, DECLARED_MAX> op{};
  std::array<std::int64_t, DECLARED_MAX> n{};
  const size_t no = k.outputs.size();
  auto release = [&] {
    for (size_t o = 0; o < no; ++o) Py_CLEAR(outs[o]);
    return false;
  };
  auto formed = [&](size_t o) { return declared::formed(k, o, [&](size_t i) { return !declared::absent(inputs[i]); }); };
  std::int64_t total = 0;
  for (size_t o = 0; o < no; ++o) {
    n[o] = formed(o) ? size_of(mv, opt, k.outputs[o]) : 0;
    total += n[o];
  }
  const bool block_of_one = read_only && s.nd == 0;
  PyObject* block = block_of_one ? PyBytes_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(total * 8)) : nullptr;
  if (block_of_one && block == nullptr) return false;
  char* at = block_of_one ? PyBytes_AS_STRING(block) : nullptr;
  for (size_t o = 0; o < no; ++o) outs[o] = nullptr;
  for (size_t o = 0; o < no; ++o) {
    if (!formed(o)) {
      outs[o] = Py_NewRef(Py_None);
      continue;
    }
    npy_intp dims[declared::STACK_MAX_DIMS + 3];
    for (int d = 0; d < s.nd; ++d) dims[d] = static_cast<npy_intp>(s.dims[d]);
    for (int d = 0; d < k.outputs[o].nd; ++d) dims[s.nd + d] = length_of(mv, opt, k.outputs[o].dims[d]);
    const int nd = s.nd + k.outputs[o].nd;
    outs[o] = block_of_one ? f64_view(nd, dims, at, block) : result_f64(nd, dims);
    if (outs[o] == nullptr) break;
    op[o] = f64_data(outs[o]);
    if (block_of_one) at += 8 * n[o];
    else if (read_only) make_read_only(outs[o]);
  }
  Py_XDECREF(block);  // (held by the views)
  if (PyErr_Occurred()) return release();
  return declared::run_taken(k, mv, t, op.data(), n.data(), opt) == OK || release();
}

// The outputs as one result (stolen): the array of a single output, else a tuple (new reference; nullptr with an
// exception set).
inline PyObject* as_result(PyObject** outs, size_t no) {
  if (no == 1) return outs[0];
  PyObject* t = PyTuple_New(static_cast<Py_ssize_t>(no));
  if (t == nullptr) {
    for (size_t o = 0; o < no; ++o) Py_CLEAR(outs[o]);
    return nullptr;
  }
  for (size_t o = 0; o < no; ++o) PyTuple_SET_ITEM(t, static_cast<Py_ssize_t>(o), outs[o]);
  return t;
}

// Whether `record` is a class whose objects are tuples (a NamedTuple: as_tuple_record makes it).
inline bool is_tuple_record(PyObject* record) {
  return PyType_Check(record) && PyType_IsSubtype(reinterpret_cast<PyTypeObject*>(record), &PyTuple_Type);
}

// The outputs (stolen) as a record of cls, a subclass of tuple (a NamedTuple): tuple.__new__(cls, outputs), as
// NamedTuple's _make makes it (cls's own __new__ only binds its arguments by name, and is passed over). New
// reference, or nullptr with an exception set.
inline PyObject* as_tuple_record(PyObject* cls, PyObject** outs, size_t no) {
  static PyObject* const tuple_new = PyObject_GetAttrString(reinterpret_cast<PyObject*>(&PyTuple_Type), "__new__");
  PyObject* t = PyTuple_New(static_cast<Py_ssize_t>(no));
  if (t == nullptr || tuple_new == nullptr) {
    Py_XDECREF(t);
    for (size_t o = 0; o < no; ++o) Py_CLEAR(outs[o]);
    return nullptr;
  }
  for (size_t o = 0; o < no; ++o) PyTuple_SET_ITEM(t, static_cast<Py_ssize_t>(o), outs[o]);
  PyObject* args[2] = {cls, t};
  PyObject* r = PyObject_Vectorcall(tuple_new, args, 2, nullptr);
  Py_DECREF(t);
  return r;
}

// Every declared algorithm (declarations.hpp's list), made once; their addresses are kept by the binding's public
// calls. Defined in bindings.cpp, so that the kernels are instantiated in one translation unit.
const std::vector<Kernel>& declared_kernels();

// N rows of a batch from raw memory (checked by the caller: shapes, overlaps): input i's rows rows_in[i] (p nullptr
// where absent; stride 0: one row broadcast), output o's rows at op[o] (nullptr where not formed), n_out[o] doubles
// each. In groups of the SIMD width where the declaration has a group kernel (the rows' roles q, v, a or τ, f_ext by
// their status arguments, and a cotangent) and no point is given (the group kernels take none), else row by row, on the thread pool. (first failing row, its status), or (−1, OK).
// The one batch path of every front end: run_batch (NumPy arrays) and the XLA FFI handler (bind_jax.cpp).
inline RowStatus run_rows(const Kernel& k, const ModelView& mv, const Rows* rows_in, double* const* op,
                          const std::int64_t* n_out, std::int64_t N, const Options& opt) {
  Rows by_arg[4], w;  // the group kernel's q, v, a or τ, f_ext; a cotangent (w_size numbers a row)
  std::int64_t w_size = 0;
  bool in_lanes = k.group != nullptr;
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    if (k.inputs[i].arg <= ARG_FEXT) by_arg[k.inputs[i].arg] = rows_in[i];
    else if (k.inputs[i].arg == ARG_W) w = rows_in[i], w_size = size_of(mv, opt, k.inputs[i]);
    else if (k.inputs[i].arg == ARG_POINT && rows_in[i].p != nullptr) in_lanes = false;  // (no role for a point)
  }
  if (const std::int64_t s = declared::check_options(k, mv, opt); s != OK) return {-1, s};
  auto state = [&](std::int64_t r, std::array<const double*, DECLARED_MAX>& ip,
                   std::array<double*, DECLARED_MAX>& opr) {
    for (size_t i = 0; i < k.inputs.size(); ++i) ip[i] = rows_in[i].row(r);
    for (size_t o = 0; o < k.outputs.size(); ++o) opr[o] = op[o] == nullptr ? nullptr : op[o] + r * n_out[o];
  };
  auto one = [&](std::int64_t r) -> std::int64_t {
    std::array<const double*, DECLARED_MAX> ip{};
    std::array<double*, DECLARED_MAX> opr{};
    state(r, ip, opr);
    return declared::run_checked(k, mv, ip.data(), opr.data(), opt);
  };
  if (!in_lanes) return for_rows(N, one);
  fdgroup::GroupArgs g{&mv, by_arg[0], by_arg[1], by_arg[2], by_arg[3], opt.gravity, op, n_out[0]};
  g.W = w;
  g.frame = opt.frame, g.reference = opt.reference;
  std::int64_t per_row = 0;
  for (size_t o = 0; o < k.outputs.size(); ++o) per_row += n_out[o];
  g.stream = fdgroup::stream_result(N, per_row);
  const fdgroup::ContactArgs contacts{opt.contacts, opt.nc,    opt.rows, opt.mu, opt.max_iter,
                                      opt.tol,      opt.singular_tol, op[1],    op[2], opt.restitution};
  if (k.options & CONTACTS) g.contacts = &contacts;  // (λ and the solve's info: the second and third outputs)
  auto check = [&](std::int64_t r) {  // (check_inputs on the rows of the group kernel's roles)
    FD_TRY(check_state(mv, by_arg[0].row(r), by_arg[1].row(r), by_arg[2].row(r), by_arg[3].row(r)));
    const double* wr = w.row(r);
    return wr == nullptr || all_finite(wr, w_size) ? OK : make_status(NONFINITE, ARG_W, first_nonfinite(wr, w_size));
  };
  return for_row_groups(N, check, one, group_kernels().*k.group, g);
}

namespace declared {

inline std::int64_t run_taken(const Kernel& k, const ModelView& mv, const Taken& t, double* const* op,
                              const std::int64_t* n_out, const Options& opt) {
  if (t.stack.nd > 0) return run_rows(k, mv, t.rows.data(), op, n_out, t.stack.N, opt).second;
  std::array<const double*, DECLARED_MAX> ip{};
  for (size_t i = 0; i < k.inputs.size(); ++i) ip[i] = t.rows[i].p;
  return run_checked(k, mv, ip.data(), op, opt);
}

}  // namespace declared

// Rows of a batch: each input (R, *shape) with R = N or 1 (broadcast), or None where optional; each output
// (N, *shape); run by run_rows. (first failing row, its status), or (−1, OK).
inline RowStatus run_batch(const Kernel& k, const ModelView& mv, const nb::sequence& inputs,
                           const nb::sequence& outputs, const Options& opt) {
  if (nb::len(inputs) != k.inputs.size() || nb::len(outputs) != k.outputs.size())
    throw nb::value_error(("featherdyn.core." + k.name + ": wrong number of operands").c_str());
  std::array<F64In, DECLARED_MAX> in;
  std::array<F64Out, DECLARED_MAX> out;
  std::array<Rows, DECLARED_MAX> rows_in{};
  std::array<double*, DECLARED_MAX> op{};
  std::array<std::int64_t, DECLARED_MAX> n_out{};
  std::int64_t N = -1;
  for (size_t o = 0; o < k.outputs.size(); ++o) {
    if (!declared::formed(k, o, [&](size_t i) { return !nb::handle(inputs[i]).is_none(); })) {
      if (!nb::handle(outputs[o]).is_none()) throw nb::value_error("featherdyn.core: None expected for an output not formed");
      continue;
    }
    if (!out[o].acquire(nb::handle(outputs[o]).ptr()))
      throw nb::type_error("out: writeable, aligned, C-contiguous native float64 arrays expected");
    n_out[o] = size_of(mv, opt, k.outputs[o]);
    const std::int64_t rows = out[o].ndim() >= 1 ? static_cast<std::int64_t>(out[o].shape(0)) : -1;
    if (rows < 0 || static_cast<std::int64_t>(out[o].size()) != rows * n_out[o] || (N >= 0 && rows != N))
      return {-1, make_status(LENGTH, ARG_OUT, rows)};
    N = rows;
    op[o] = out[o].data();
  }
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    nb::handle x = inputs[i];
    const Operand& spec = k.inputs[i];
    if (x.is_none()) {
      if (!spec.optional) return {-1, make_status(LENGTH, spec.arg, -1)};
      continue;
    }
    if (!in[i].acquire(x.ptr())) throw nb::type_error("featherdyn.core: native float64 arrays expected");
    const std::int64_t n = size_of(mv, opt, spec);
    const std::int64_t R = in[i].ndim() >= 1 ? static_cast<std::int64_t>(in[i].shape(0)) : -1;
    if (!(R == N || R == 1) || static_cast<std::int64_t>(in[i].size()) != R * n)
      return {-1, make_status(LENGTH, spec.arg, R)};
    rows_in[i] = Rows{in[i].data(), R == 1 ? 0 : n};
    for (size_t o = 0; o < k.outputs.size(); ++o)
      if (op[o] != nullptr && overlaps(op[o], N * n_out[o], in[i].data(), R * n))
        return {-1, make_status(OVERLAP, spec.arg, 0)};
  }
  return run_rows(k, mv, rows_in.data(), op.data(), n_out.data(), N, opt);
}

}  // namespace fdcore

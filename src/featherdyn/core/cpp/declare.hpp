// Declared algorithms (docs/architecture.md, "One declaration per algorithm"): an algorithm states its name,
// its operands with symbolic shapes and its kernel on one state, once; the templates here make every front
// end of the binding from that — the one-state call into given arrays (`into`), the one-state call that
// allocates its results (`fresh`) and the batch on the thread pool (`batch`) — and `Kernel` carries the
// declaration to Python, where the public function, `out=`, Dask and `fd.compile`'s method are made from it
// (featherdyn/api/declared.py).
//
// A declaration D is a struct with
//     static constexpr const char* name;
//     static constexpr Operand inputs[] = {...}, outputs[] = {...};
//     static std::int64_t run(const ModelView&, const double* const* in, double* const* out);
// `run` gets each input (nullptr for an absent optional one) and each output, all of the declared shapes and
// already checked (lengths, finiteness, unit quaternions), and returns OK or a status (checks.hpp: SINGULAR
// naming the joint, ...); the front ends then check the outputs for overflow (NONFINITE).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "boundary.hpp"
#include "public_calls.hpp"

namespace fdcore {

// A symbolic length: the model's nq, nv or nb; a non-negative value is a literal length.
enum SymbolicLength : int { NQ = -1, NV = -2, NB = -3 };

// An input or output: its name, the status argument that names it in an error (checks.hpp: ARG_Q for q, ARG_V,
// ARG_A for q̈ or τ, ARG_FEXT, ARG_OUT), its shape (up to three lengths) and whether an input may be absent.
struct Operand {
  const char* name;
  std::int64_t arg;
  int dims[3];
  int nd;
  bool optional;
};

constexpr int DECLARED_MAX = 6;  // inputs, and outputs, of one declaration at most

inline std::int64_t length_of(const ModelView& mv, int d) {
  return d == NQ ? mv.nq : d == NV ? mv.nv : d == NB ? mv.nb : d;
}
inline std::int64_t size_of(const ModelView& mv, const Operand& o) {
  std::int64_t n = 1;
  for (int k = 0; k < o.nd; ++k) n *= length_of(mv, o.dims[k]);
  return n;
}

// A declaration with its type erased: what the binding and Python see. `free` and `bound` are its public
// calls' parameters (public_calls.hpp): (model, *inputs) for fd.<name>, (*inputs) for fd.compile's method.
struct Kernel {
  std::string name;
  std::vector<Operand> inputs, outputs;
  std::int64_t (*run)(const ModelView&, const double* const* in, double* const* out);
  PublicCallKind free{}, bound{};
};

PyObject* declared_path(PublicCall* f, PyObject* const* args);  // (bind_public_calls.cpp)

template <class D>
Kernel declare() {
  static_assert(std::size(D::inputs) < PUBLIC_CALL_MAX_ARGS && std::size(D::inputs) <= DECLARED_MAX &&
                std::size(D::outputs) <= DECLARED_MAX);
  Kernel k{D::name, std::vector<Operand>(std::begin(D::inputs), std::end(D::inputs)),
           std::vector<Operand>(std::begin(D::outputs), std::end(D::outputs)), &D::run};
  int required = 0;
  for (const Operand& o : D::inputs) required += o.optional ? 0 : 1;
  const int n = static_cast<int>(std::size(D::inputs));
  k.free = PublicCallKind{{"model"}, n + 1, n + 1, required + 1, &declared_path};
  k.bound = PublicCallKind{{}, n, n, required, &declared_path};
  for (int i = 0; i < n; ++i) k.free.names[i + 1] = k.bound.names[i] = D::inputs[i].name;
  return k;
}

namespace declared {

// The state check of the inputs (finiteness, unit quaternions): by the status argument each one names.
inline std::int64_t check_inputs(const Kernel& k, const ModelView& mv, const double* const* in) {
  const double* by_arg[4] = {nullptr, nullptr, nullptr, nullptr};  // q, v, a or τ, f_ext
  for (size_t i = 0; i < k.inputs.size(); ++i)
    if (k.inputs[i].arg <= ARG_FEXT) by_arg[k.inputs[i].arg] = in[i];
  return check_state(mv, by_arg[0], by_arg[1], by_arg[2], by_arg[3]);
}

// Run the kernel on one checked state and check its outputs for overflow.
inline std::int64_t run_checked(const Kernel& k, const ModelView& mv, const double* const* in, double* const* out) {
  FD_TRY(check_inputs(k, mv, in));
  FD_TRY(k.run(mv, in, out));
  for (size_t o = 0; o < k.outputs.size(); ++o) FD_TRY(finite_result(out[o], size_of(mv, k.outputs[o])));
  return OK;
}

// An operand of one state: an array of exactly the declared shape (a wrong one: a LENGTH status naming it).
template <class A>
std::int64_t exact(const A& x, const ModelView& mv, const Operand& o) {
  bool same = x.ndim() == static_cast<size_t>(o.nd);
  for (int d = 0; same && d < o.nd; ++d) same = static_cast<std::int64_t>(x.shape(d)) == length_of(mv, o.dims[d]);
  return same ? OK : make_status(LENGTH, o.arg, x.ndim() == 1 ? static_cast<std::int64_t>(x.shape(0)) : -1);
}

// As many inputs and outputs as the declaration has (a caller's mistake, not the user's: ValueError).
inline void check_counts(const Kernel& k, const nb::sequence& inputs, const nb::sequence& outputs) {
  if (nb::len(inputs) != k.inputs.size() || nb::len(outputs) != k.outputs.size())
    throw nb::value_error(("featherdyn.core." + k.name + ": wrong number of operands").c_str());
}

// An output array: writeable native float64 (nanobind's TypeError otherwise, for the Python front end).
inline void acquire_output(F64Out& out, nb::handle x) {
  if (!out.acquire(x.ptr())) throw nb::type_error("featherdyn.core: writeable native float64 arrays expected");
}

}  // namespace declared

// One state into given outputs: OK or the status of the first failure (lengths, the state, overlap, the kernel).
// nanobind refuses anything but exact native float64 arrays: a TypeError, for the Python front end to convert.
inline std::int64_t run_into(const Kernel& k, const ModelData& md, const nb::sequence& inputs,
                             const nb::sequence& outputs) {
  const ModelView& mv = md.view;
  declared::check_counts(k, inputs, outputs);
  std::array<F64In, DECLARED_MAX> in;
  std::array<F64Out, DECLARED_MAX> out;
  std::array<const double*, DECLARED_MAX> ip{};
  std::array<double*, DECLARED_MAX> op{};
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    nb::handle x = inputs[i];
    if (x.is_none()) {
      if (!k.inputs[i].optional) return make_status(LENGTH, k.inputs[i].arg, -1);
      continue;
    }
    if (!in[i].acquire(x.ptr())) throw nb::type_error("featherdyn.core: native float64 arrays expected");
    FD_TRY(declared::exact(in[i], mv, k.inputs[i]));
    ip[i] = in[i].data();
  }
  for (size_t o = 0; o < k.outputs.size(); ++o) {
    declared::acquire_output(out[o], outputs[o]);
    FD_TRY(declared::exact(out[o], mv, k.outputs[o]));
    op[o] = out[o].data();
    const std::int64_t n = size_of(mv, k.outputs[o]);
    for (size_t i = 0; i < k.inputs.size(); ++i)
      if (overlaps(op[o], n, ip[i], size_of(mv, k.inputs[i]))) return make_status(OVERLAP, k.inputs[i].arg, 0);
    for (size_t p = 0; p < o; ++p)
      if (overlaps(op[o], n, op[p], size_of(mv, k.outputs[p]))) return make_status(OVERLAP, ARG_OUT, 0);
  }
  return declared::run_checked(k, mv, ip.data(), op.data());
}

// One state, the results allocated here: the result (one array, or a tuple of them), or None for anything
// run_into would refuse with a status (the Python front end then words it).
inline nb::object run_fresh(const Kernel& k, const ModelData& md, const nb::sequence& inputs) {
  const ModelView& mv = md.view;
  nb::list outs;
  for (const Operand& o : k.outputs) {
    npy_intp dims[3];
    for (int d = 0; d < o.nd; ++d) dims[d] = length_of(mv, o.dims[d]);
    PyObject* a = new_f64(o.nd, dims);
    if (a == nullptr) throw nb::python_error();
    outs.append(nb::steal(a));
  }
  if (run_into(k, md, inputs, nb::borrow<nb::sequence>(outs)) != OK) return nb::none();
  return k.outputs.size() == 1 ? nb::object(outs[0]) : nb::object(nb::tuple(outs));
}

// Rows of a batch: each input (R, *shape) with R = N or 1 (broadcast), or None where optional; each output
// (N, *shape). (first failing row, its status), or (−1, OK).
inline RowStatus run_batch(const Kernel& k, const ModelData& md, const nb::sequence& inputs,
                           const nb::sequence& outputs) {
  const ModelView& mv = md.view;
  declared::check_counts(k, inputs, outputs);
  std::array<F64In, DECLARED_MAX> in;
  std::array<F64Out, DECLARED_MAX> out;
  std::array<Rows, DECLARED_MAX> rows_in{};
  std::array<double*, DECLARED_MAX> op{};
  std::array<std::int64_t, DECLARED_MAX> n_out{};
  std::int64_t N = -1;
  for (size_t o = 0; o < k.outputs.size(); ++o) {
    declared::acquire_output(out[o], outputs[o]);
    n_out[o] = size_of(mv, k.outputs[o]);
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
    const std::int64_t n = size_of(mv, spec);
    const std::int64_t R = in[i].ndim() >= 1 ? static_cast<std::int64_t>(in[i].shape(0)) : -1;
    if (!(R == N || R == 1) || static_cast<std::int64_t>(in[i].size()) != R * n)
      return {-1, make_status(LENGTH, spec.arg, R)};
    rows_in[i] = Rows{in[i].data(), R == 1 ? 0 : n};
    for (size_t o = 0; o < k.outputs.size(); ++o)
      if (overlaps(op[o], N * n_out[o], in[i].data(), R * n)) return {-1, make_status(OVERLAP, spec.arg, 0)};
  }
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    std::array<const double*, DECLARED_MAX> ip{};
    std::array<double*, DECLARED_MAX> opr{};
    for (size_t i = 0; i < k.inputs.size(); ++i) ip[i] = rows_in[i].row(r);
    for (size_t o = 0; o < k.outputs.size(); ++o) opr[o] = op[o] + r * n_out[o];
    return declared::run_checked(k, mv, ip.data(), opr.data());
  });
}

}  // namespace fdcore

// The XLA FFI handler of featherdyn.jax (docs/frameworks.md; docs/architecture.md, "The glue"): one handler for
// every declared algorithm, its buffers run by the same batch path as NumPy's (declare.hpp: run_rows). Compiled
// when the build finds XLA's FFI headers (jaxlib's include directory: CMakeLists.txt); without them the module
// has no `jax_handler` and featherdyn.jax says so.
//
//     featherdyn_declared(*inputs, kernel: int64, key: int64, present: int64) -> *outputs
//
// `kernel` indexes declared_kernels(); `key` an entry registered from Python (a model and a call's Options, held
// alive there); bit i of `present` whether input i is passed (optional inputs may be absent). Each buffer is
// float64 with the declared shape last and any leading (batch) dimensions; an input's rows are 1 (broadcast) or
// the outputs' N. A status (non-finite input, a singular mass matrix …) is the handler's error, naming the row.
#include <algorithm>
#include <iterator>
#include <mutex>
#include <string>
#include <vector>

#include "declare.hpp"
#include "entry_points.hpp"

#if defined(FEATHERDYN_JAX_FFI)
#include "xla/ffi/api/ffi.h"

namespace nb = nanobind;
namespace ffi = xla::ffi;
using namespace fdcore;

namespace {

struct Entry {
  const ModelData* model;
  Options options;
};

// Entries are only appended (under the lock); the handler reads them under the lock too.
std::mutex entries_lock;
std::vector<Entry>& entries() {
  static std::vector<Entry> e;
  return e;
}

const char* const CODE_NAMES[] = {"ok", "wrong length", "non-finite value", "quaternion off unit norm",
                                  "singular mass matrix", "output overlaps an input", "no mass",
                                  "dependent constraints"};

std::string status_words(const Kernel& k, std::int64_t row, std::int64_t status) {
  const std::int64_t code = status & 7, arg = (status >> 3) & 31, index = status >> 8;
  std::string s = "featherdyn." + k.name + ": ";
  if (row >= 0) s += "row " + std::to_string(row) + ": ";
  s += code < 8 ? CODE_NAMES[code] : "status " + std::to_string(status);
  if (arg < static_cast<std::int64_t>(std::size(ARG_WORDS)))
    s += std::string(" (") + ARG_WORDS[arg] + ", index " + std::to_string(index) + ")";
  return s;
}

ffi::Error declared_call(ffi::RemainingArgs args, ffi::RemainingRets rets, std::int64_t kernel, std::int64_t key,
                         std::int64_t present) {
  const std::vector<Kernel>& kernels = declared_kernels();
  if (kernel < 0 || kernel >= static_cast<std::int64_t>(kernels.size()))
    return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn: unknown kernel");
  const Kernel& k = kernels[static_cast<size_t>(kernel)];
  Entry e;
  {
    std::lock_guard<std::mutex> guard(entries_lock);
    if (key < 0 || key >= static_cast<std::int64_t>(entries().size()))
      return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn: unknown model entry");
    e = entries()[static_cast<size_t>(key)];
  }
  const ModelView& mv = e.model->view;
  if (rets.size() != k.outputs.size())
    return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": wrong number of results");
  std::array<double*, DECLARED_MAX> op{};
  std::array<std::int64_t, DECLARED_MAX> n_out{};
  std::int64_t N = -1;
  for (size_t o = 0; o < k.outputs.size(); ++o) {
    auto r = rets.get<ffi::AnyBuffer>(o);
    if (r.has_error()) return r.error();
    ffi::Result<ffi::AnyBuffer> buf = r.value();
    if (buf->element_type() != ffi::DataType::F64)
      return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": float64 results expected");
    n_out[o] = size_of(mv, e.options, k.outputs[o]);
    const std::int64_t rows = n_out[o] > 0 ? static_cast<std::int64_t>(buf->element_count()) / n_out[o] : 0;
    if (rows * n_out[o] != static_cast<std::int64_t>(buf->element_count()) || (N >= 0 && rows != N))
      return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": results of mixed batches");
    N = rows;
    op[o] = buf->typed_data<double>();
    if (!declared::formed(k, o, [&](size_t i) { return ((present >> i) & 1) != 0; })) {  // zeros, not formed
      std::fill(op[o], op[o] + buf->element_count(), 0.0);
      op[o] = nullptr;
    }
  }
  std::array<Rows, DECLARED_MAX> rows_in{};
  size_t a = 0;
  for (size_t i = 0; i < k.inputs.size(); ++i) {
    if (!((present >> i) & 1)) {
      if (!k.inputs[i].optional)
        return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": missing input");
      continue;
    }
    auto x = args.get<ffi::AnyBuffer>(a++);
    if (x.has_error()) return x.error();
    if (x.value().element_type() != ffi::DataType::F64)
      return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": float64 inputs expected");
    const std::int64_t n = size_of(mv, e.options, k.inputs[i]);
    const std::int64_t R = static_cast<std::int64_t>(x.value().element_count()) / n;
    if (R * n != static_cast<std::int64_t>(x.value().element_count()) || !(R == N || R == 1))
      return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": inputs of mixed batches");
    rows_in[i] = Rows{x.value().typed_data<double>(), R == 1 ? 0 : n};
  }
  if (a != args.size())
    return ffi::Error(ffi::ErrorCode::kInvalidArgument, "featherdyn." + k.name + ": wrong number of inputs");
  const RowStatus s = run_rows(k, mv, rows_in.data(), op.data(), n_out.data(), N, e.options);
  if (s.second != OK) return ffi::Error(ffi::ErrorCode::kInvalidArgument, status_words(k, s.first, s.second));
  return ffi::Error::Success();
}

}  // namespace

XLA_FFI_DEFINE_HANDLER_SYMBOL(featherdyn_declared, declared_call,
                              ffi::Ffi::Bind()
                                  .RemainingArgs()
                                  .RemainingRets()
                                  .Attr<std::int64_t>("kernel")
                                  .Attr<std::int64_t>("key")
                                  .Attr<std::int64_t>("present"));

void fdcore::bind_jax(nb::module_& m) {
  m.def("jax_handler", [] { return nb::capsule(reinterpret_cast<void*>(&featherdyn_declared)); },
        "the XLA FFI handler of every declared algorithm (a capsule for jax.ffi.register_ffi_target)");
  m.def("jax_entry", [](const ModelData& md, const CallOptions* options) {
          std::lock_guard<std::mutex> guard(entries_lock);
          entries().push_back(Entry{&md, options_of(md, options)});
          return static_cast<std::int64_t>(entries().size() - 1);
        }, nb::arg("model"), nb::arg("options").none() = nb::none(),
        "register a model and a call's options for the handler; the caller keeps both alive");
  nb::list names;
  for (const Kernel& k : declared_kernels()) names.append(k.name);
  m.attr("kernel_order") = names;
}

#else

void fdcore::bind_jax(nanobind::module_&) {}

#endif

// The public functions' calls of one state or a stack of them finished in C (public_calls.hpp; docs/architecture.md, "The public
// layer"): the declared algorithms' one path (declared_path), and the record a public function makes of its outputs.
#include <string>

#include "declarations.hpp"
#include "public_calls.hpp"
#include "entry_points.hpp"

namespace nb = nanobind;
using namespace fdcore;

namespace {

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

// The gravity flag (absent: True; exactly True or False, anything else declines).
bool flag_arg(PyObject* x, bool& out) {
  out = x == nullptr || x == Py_True;
  return x == nullptr || x == Py_True || x == Py_False;
}

// The public result of a declared call's outputs (stolen; None where not formed): the outputs themselves (one
// array, or a tuple), or the record the public function declares of them (`record`, the last of its constants): a
// callable, called with the outputs (a NamedTuple class: made by as_tuple_record, declare.hpp); or (cls,
// (descriptor, source), ...) (made by `record_of`): a new cls
// (object.__new__) whose fields are set through their data descriptors, as object.__setattr__ sets them (a frozen
// record's own __setattr__ is passed over), each to an output (source: its index; the outputs were made as
// read-only views: run_fresh), the model argument (source −1) or the object given. New reference, or nullptr
// with an exception set.
PyObject* result_of(PyObject* record, PyObject* model, PyObject** outs, size_t no) {
  if (record == Py_None) return as_result(outs, no);
  if (is_tuple_record(record)) return as_tuple_record(record, outs, no);
  nb::object held[DECLARED_MAX];
  for (size_t o = 0; o < no; ++o) held[o] = nb::steal(outs[o]);
  if (!PyTuple_CheckExact(record)) return PyObject_Vectorcall(record, outs, no, nullptr);
  PyObject* cls = PyTuple_GET_ITEM(record, 0);
  nb::object x = nb::steal(PyType_GenericNew(reinterpret_cast<PyTypeObject*>(cls), nullptr, nullptr));
  if (!x.is_valid()) return nullptr;
  for (Py_ssize_t f = 1; f < PyTuple_GET_SIZE(record); ++f) {
    PyObject* descriptor = PyTuple_GET_ITEM(PyTuple_GET_ITEM(record, f), 0);
    PyObject* source = PyTuple_GET_ITEM(PyTuple_GET_ITEM(record, f), 1);
    PyObject* value = source;
    if (PyLong_CheckExact(source)) {
      const long at = PyLong_AsLong(source);
      value = at < 0 ? model : outs[at];
    }
    if (Py_TYPE(descriptor)->tp_descr_set(descriptor, x.ptr(), value) != 0) return nullptr;
  }
  return x.release().ptr();
}

// The core's Model a compiled model's method is bound to (f->bound).
const ModelData& bound_model(const PublicCall* f) { return *nb::inst_ptr<ModelData>(nb::handle(f->bound)); }

}  // namespace pc
}  // namespace

// fd.<name>(model, *inputs, ...) of a declared algorithm (extra = (CoreHandle, its Kernel, LOCAL, WORLD,
// LOCAL_WORLD_ALIGNED, record)), or fd.compile's method (*inputs, ...) bound to the core's Model (extra = (its
// Kernel, the frame table, LOCAL, WORLD, LOCAL_WORLD_ALIGNED, record)): its arguments where the Kernel's slots say —
// a frame by name or index, a reference by identity with the enums; out= absent: run_fresh and the result its
// record makes (pc::result_of), else run_into the given array (a tuple of them for several outputs), returned, or
// with a NamedTuple record the record of them (with any other record, declined: the Python path writes the arrays
// and makes the record of them).
PyObject* fdcore::declared_path(PublicCall* f, PyObject* const* a) {
  const bool is_bound = f->bound != nullptr;
  const Kernel& k = *nb::inst_ptr<Kernel>(nb::handle(PyTuple_GET_ITEM(f->extra, is_bound ? 0 : 1)));
  const Slots& at = is_bound ? k.bound_at : k.free_at;
  const ModelData* md = nullptr;
  PyObject* frames = nullptr;
  if (is_bound) md = &pc::bound_model(f), frames = PyTuple_GET_ITEM(f->extra, 1);
  else if (!pc::model_of(f, a[0], md, frames)) return nullptr;
  Options opt;
  if (at.gravity >= 0 && !pc::flag_arg(a[at.gravity], opt.gravity)) return nullptr;
  if (at.frame >= 0 && !pc::frame_of(a[at.frame], frames, md->view.nf, opt.frame)) return nullptr;
  if (at.reference >= 0 && !pc::reference_of(f, a[at.reference], 2, opt.reference)) return nullptr;
  PyObject* in[DECLARED_MAX];  // (the inputs in the declaration's order; a point comes after the options)
  for (size_t i = 0; i < k.inputs.size(); ++i) in[i] = a[at.input[i]];
  PyObject* out = a[at.out];
  PyObject* record = PyTuple_GET_ITEM(f->extra, 5);
  if (out == nullptr || out == Py_None) {
    PyObject* outs[DECLARED_MAX];
    if (!run_fresh(k, md->view, in, opt, outs, PyTuple_CheckExact(record))) return nullptr;
    return pc::result_of(record, is_bound ? Py_None : a[0], outs, k.outputs.size());
  }
  const Py_ssize_t no = static_cast<Py_ssize_t>(k.outputs.size());
  // a NamedTuple record of several outputs, each always formed: the record of the given arrays themselves
  bool tuple_record = record != Py_None && is_tuple_record(record) && no > 1;
  for (Py_ssize_t o = 0; tuple_record && o < no; ++o) tuple_record = k.outputs[static_cast<size_t>(o)].when < 0;
  if (record != Py_None && !tuple_record) return nullptr;
  PyObject* outs[DECLARED_MAX] = {out};
  if (no > 1) {
    if (!PyTuple_CheckExact(out) || PyTuple_GET_SIZE(out) != no) return nullptr;
    for (Py_ssize_t o = 0; o < no; ++o) outs[o] = PyTuple_GET_ITEM(out, o);
  }
  if (run_into(k, md->view, in, outs, opt) != OK) return nullptr;
  if (!tuple_record) return Py_NewRef(out);
  for (Py_ssize_t o = 0; o < no; ++o) Py_INCREF(outs[o]);  // (as_tuple_record steals them)
  return as_tuple_record(record, outs, static_cast<size_t>(no));
}

namespace {
namespace pc {

// A record as result_of reads it (new reference; nullptr with an exception set): None, a callable, or — from
// (cls, (field name, source), ...) with each source an output's index, −1 (the model argument: not for a bound
// method) or any other object — (cls, (the data descriptor of cls's field, source), ...).
PyObject* record_of(PyObject* record, const Kernel& k, bool is_bound) {
  auto refuse = [] {
    PyErr_SetString(PyExc_ValueError, "declared_call: record must be None, a callable or (cls, (field, source), ...)");
    return nullptr;
  };
  if (record == Py_None || (!PyTuple_CheckExact(record) && PyCallable_Check(record))) return Py_NewRef(record);
  if (!PyTuple_CheckExact(record)) return refuse();
  const Py_ssize_t n = PyTuple_Size(record);
  if (n < 1 || !PyType_Check(PyTuple_GetItem(record, 0))) return refuse();
  nb::handle cls = PyTuple_GetItem(record, 0);
  nb::list fields;
  fields.append(cls);
  for (Py_ssize_t i = 1; i < n; ++i) {
    PyObject* f = PyTuple_GetItem(record, i);
    if (!PyTuple_CheckExact(f) || PyTuple_Size(f) != 2 || !PyUnicode_Check(PyTuple_GetItem(f, 0))) return refuse();
    PyObject* source = PyTuple_GetItem(f, 1);
    if (PyLong_CheckExact(source)) {
      int overflow = 0;
      const long at = PyLong_AsLongAndOverflow(source, &overflow);
      if (overflow != 0 || at < -1 || at >= static_cast<long>(k.outputs.size()) || (at == -1 && is_bound)) return refuse();
    }
    nb::object d = nb::steal(PyObject_GetAttr(cls.ptr(), PyTuple_GetItem(f, 0)));
    if (!d.is_valid() || !PyDescr_IsData(d.ptr()) || Py_TYPE(d.ptr())->tp_descr_set == nullptr) {
      PyErr_Clear();
      PyErr_Format(PyExc_ValueError, "declared_call: %S is not a field of %S", PyTuple_GetItem(f, 0), cls.ptr());
      return nullptr;
    }
    fields.append(nb::make_tuple(d, nb::handle(source)));
  }
  return PyList_AsTuple(fields.ptr());
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

}  // namespace

void fdcore::bind_public_calls(nb::module_& m) {
  m.def("declared_call", [](const Kernel& k, nb::handle general, nb::handle extra, nb::handle bound) {
          const bool is_bound = !bound.is_none();
          if (!PyTuple_Check(extra.ptr()) || PyTuple_GET_SIZE(extra.ptr()) != 6 ||
              !nb::isinstance<Kernel>(nb::handle(PyTuple_GET_ITEM(extra.ptr(), is_bound ? 0 : 1))) ||
              nb::inst_ptr<Kernel>(nb::handle(PyTuple_GET_ITEM(extra.ptr(), is_bound ? 0 : 1))) != &k ||
              (is_bound && !PyDict_CheckExact(PyTuple_GET_ITEM(extra.ptr(), 1))))
            throw nb::value_error("declared_call: extra must be (CoreHandle, kernel, LOCAL, WORLD, LOCAL_WORLD_ALIGNED, "
                                  "record), or (kernel, frame table, LOCAL, WORLD, LOCAL_WORLD_ALIGNED, record) when bound");
          if (is_bound && !nb::isinstance<ModelData>(bound)) throw nb::type_error("declared_call: the core's Model expected");
          // the constants as the fast path reads them: the record's fields as their descriptors
          nb::object record = nb::steal(pc::record_of(PyTuple_GET_ITEM(extra.ptr(), 5), k, is_bound));
          if (!record.is_valid()) throw nb::python_error();
          nb::object constants = nb::steal(PyTuple_GetSlice(extra.ptr(), 0, 5));
          if (!constants.is_valid()) throw nb::python_error();
          constants = nb::steal(PySequence_Concat(constants.ptr(), nb::make_tuple(record).ptr()));
          if (!constants.is_valid()) throw nb::python_error();
          PyObject* r = make_public_call(is_bound ? &k.bound : &k.free, general.ptr(), constants.ptr(),
                                         is_bound ? bound.ptr() : nullptr);
          if (r == nullptr) throw nb::python_error();
          return nb::steal(r);
        }, nb::arg("kernel"), nb::arg("general"), nb::arg("extra"), nb::arg("bound").none(),
        "a declared algorithm's public function (or bound method) whose one-state calls run here");
  m.def("set_public_calls", [](bool on) { public_calls_enabled = on; }, nb::arg("enabled"),
        "off: every call of a public_call goes to its Python function (the default backend is 'reference')");
  pc::init();
}

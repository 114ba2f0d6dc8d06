// PublicCall: a public function whose common call — one state, or a stack of them (declare.hpp: take) — is
// finished here, in C, and every other call handed unchanged to the Python function it wraps
// (docs/architecture.md, "The public functions' one-state path", and "A stack of states").
//
// Why: the cheapest Python function around a 0.3 µs kernel costs 0.15–0.25 µs (the call, the
// backend test, the model's handle, the frame name, the reference enum), which kept
// fd.frame_jacobian at 1.0× Pinocchio and fd.frame_placement at 2–3× (building a PluckerTransform
// in Python: 1.2 µs). A PublicCall binds the arguments (positional or by keyword, against the
// names the kind declares), and its kind's fast path either returns the result or declines
// (nullptr without an exception); a declined call — any other keyword, a list, float32, a Dask
// array, an unknown frame, a bad state, the reference backend as the default — goes to the
// Python function with the very same arguments, which converts, computes or words the error.
// So the fast path never has to reproduce an error message: it only ever returns right results.
//
// The object looks like the function it wraps: functools.update_wrapper copies __name__,
// __qualname__, __module__, __doc__ and sets __wrapped__ (inspect.signature follows it), and it
// pickles by name like a function.
#pragma once

#include <Python.h>

#include <cstddef>

namespace fdcore {

struct PublicCall;

// The fast path of one kind: args holds the bound arguments (nullptr where not given); returns a
// new reference, or nullptr with no exception set to decline, or nullptr with an exception set.
using FastPath = PyObject* (*)(PublicCall* self, PyObject* const* args);

constexpr int PUBLIC_CALL_MAX_ARGS = 8;

struct PublicCallKind {
  const char* names[PUBLIC_CALL_MAX_ARGS];  // the parameters the fast path binds, in order
  int nparams;
  int positional;  // how many may be given by position (the rest are keyword-only)
  int required;    // the first `required` must be given
  FastPath path;
};

struct PublicCall {
  PyObject_HEAD
  vectorcallfunc vectorcall;
  PyObject* general;  // the Python function: every declined call, unchanged
  PyObject* extra;    // the kind's constants (a tuple)
  PyObject* bound;    // the core model of a compiled model's method, else nullptr
  PyObject* dict;     // __name__, __doc__, __wrapped__, ... (functools.update_wrapper)
  const PublicCallKind* kind;
  PyObject* names[PUBLIC_CALL_MAX_ARGS];  // the parameter names, interned
  // the last model's handle and what the fast path reads of it (strong references: the handle's
  // address cannot be reused while it is cached)
  PyObject* last_handle;
  PyObject* last_model;  // the core model (ModelData) of last_handle
  PyObject* last_frames;
};

// Off while the default backend is "reference" (fd.set_default_backend): every call declines.
inline bool public_calls_enabled = true;

namespace public_call_detail {

// Bind positional arguments then keywords to the kind's parameters; false (decline) for an unknown
// keyword, a repeated or missing argument: the Python function raises the TypeError.
inline bool bind(const PublicCall* f, PyObject* const* args, size_t nargsf, PyObject* kwnames,
                 PyObject** out) {
  const PublicCallKind& k = *f->kind;
  const Py_ssize_t npos = PyVectorcall_NARGS(nargsf);
  if (npos > k.positional) return false;
  for (int i = 0; i < k.nparams; ++i) out[i] = i < npos ? args[i] : nullptr;
  if (kwnames != nullptr) {
    const Py_ssize_t nkw = PyTuple_GET_SIZE(kwnames);
    for (Py_ssize_t j = 0; j < nkw; ++j) {
      PyObject* name = PyTuple_GET_ITEM(kwnames, j);
      int slot = -1;
      for (int i = 0; i < k.nparams && slot < 0; ++i)
        if (name == f->names[i]) slot = i;  // keyword names are interned, as the parameter names
      for (int i = 0; i < k.nparams && slot < 0; ++i)
        if (PyUnicode_Compare(name, f->names[i]) == 0) slot = i;
      if (PyErr_Occurred()) PyErr_Clear();
      if (slot < 0 || out[slot] != nullptr) return false;
      out[slot] = args[npos + j];
    }
  }
  for (int i = 0; i < k.required; ++i)
    if (out[i] == nullptr) return false;
  return true;
}

inline PyObject* call(PyObject* self, PyObject* const* args, size_t nargsf, PyObject* kwnames) {
  PublicCall* f = reinterpret_cast<PublicCall*>(self);
  if (public_calls_enabled) {
    PyObject* bound[PUBLIC_CALL_MAX_ARGS];
    if (bind(f, args, nargsf, kwnames, bound)) {
      PyObject* r = f->kind->path(f, bound);
      if (r != nullptr || PyErr_Occurred()) return r;
    }
  }
  return PyObject_Vectorcall(f->general, args, nargsf, kwnames);
}

inline int traverse(PyObject* self, visitproc visit, void* arg) {
  PublicCall* f = reinterpret_cast<PublicCall*>(self);
  Py_VISIT(f->general);
  Py_VISIT(f->extra);
  Py_VISIT(f->bound);
  Py_VISIT(f->dict);
  Py_VISIT(f->last_handle);
  Py_VISIT(f->last_model);
  Py_VISIT(f->last_frames);
  return 0;
}

inline int clear(PyObject* self) {
  PublicCall* f = reinterpret_cast<PublicCall*>(self);
  Py_CLEAR(f->general);
  Py_CLEAR(f->extra);
  Py_CLEAR(f->bound);
  Py_CLEAR(f->dict);
  Py_CLEAR(f->last_handle);
  Py_CLEAR(f->last_model);
  Py_CLEAR(f->last_frames);
  for (PyObject*& n : f->names) Py_CLEAR(n);
  return 0;
}

inline void dealloc(PyObject* self) {
  PyObject_GC_UnTrack(self);
  clear(self);
  Py_TYPE(self)->tp_free(self);
}

// "<function featherdyn.api.kinematics.frame_jacobian (one-state calls in the compiled core)>"
inline PyObject* repr(PyObject* self) {
  PyObject* module = PyObject_GetAttrString(self, "__module__");
  PyObject* name = module != nullptr ? PyObject_GetAttrString(self, "__qualname__") : nullptr;
  PyObject* r = name != nullptr ? PyUnicode_FromFormat("<function %S.%S (one-state calls in the compiled core)>",
                                                       module, name)
                                : nullptr;
  Py_XDECREF(module);
  Py_XDECREF(name);
  return r;
}

// Read as an attribute of a class or an instance, the object itself (as a builtin function: it does not bind).
// Having __get__ (and no __set__) also makes inspect.isroutine true, so help() documents it as a function,
// with the signature of __wrapped__.
inline PyObject* descr_get(PyObject* self, PyObject*, PyObject*) { return Py_NewRef(self); }

// Pickled by name, like a function: the module attribute of the name __qualname__ (set by
// functools.update_wrapper) is this object.
inline PyObject* reduce(PyObject* self, PyObject*) {
  return PyObject_GetAttrString(self, "__qualname__");
}

inline PyMethodDef methods[] = {
    {"__reduce__", reduce, METH_NOARGS, "pickled by name, like a function"},
    {nullptr, nullptr, 0, nullptr},
};

inline PyGetSetDef getset[] = {
    {"__dict__", PyObject_GenericGetDict, PyObject_GenericSetDict, nullptr, nullptr},
    {nullptr, nullptr, nullptr, nullptr, nullptr},
};

// A static type's storage: zeroed, with the object header PyVarObject_HEAD_INIT(nullptr, 0) writes.
inline PyTypeObject zeroed_type() {
  PyTypeObject t{};
  const PyVarObject head = {PyObject_HEAD_INIT(nullptr) 0};
  t.ob_base = head;
  return t;
}

inline PyTypeObject type = zeroed_type();

}  // namespace public_call_detail

// The type, readied once (at import).
inline PyTypeObject* public_call_type() {
  namespace d = public_call_detail;
  if (d::type.tp_flags & Py_TPFLAGS_READY) return &d::type;
  d::type.tp_name = "featherdyn.core._core.PublicCall";
  d::type.tp_basicsize = sizeof(PublicCall);
  d::type.tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC | Py_TPFLAGS_HAVE_VECTORCALL;
  d::type.tp_doc = "A public function whose one-state calls run in the compiled core (see its __wrapped__).";
  d::type.tp_vectorcall_offset = offsetof(PublicCall, vectorcall);
  d::type.tp_call = PyVectorcall_Call;
  d::type.tp_dictoffset = offsetof(PublicCall, dict);
  d::type.tp_getattro = PyObject_GenericGetAttr;
  d::type.tp_setattro = PyObject_GenericSetAttr;
  d::type.tp_traverse = d::traverse;
  d::type.tp_clear = d::clear;
  d::type.tp_dealloc = d::dealloc;
  d::type.tp_repr = d::repr;
  d::type.tp_descr_get = d::descr_get;
  d::type.tp_methods = d::methods;
  d::type.tp_getset = d::getset;
  if (PyType_Ready(&d::type) != 0) return nullptr;
  return &d::type;
}

// A new PublicCall of `kind` around `general` (new reference; nullptr with an exception set).
inline PyObject* make_public_call(const PublicCallKind* kind, PyObject* general, PyObject* extra, PyObject* bound) {
  PyTypeObject* t = public_call_type();
  if (t == nullptr) return nullptr;
  if (!PyCallable_Check(general) || !PyTuple_Check(extra)) {
    PyErr_SetString(PyExc_TypeError, "PublicCall: expected a callable and a tuple of constants");
    return nullptr;
  }
  PublicCall* f = PyObject_GC_New(PublicCall, t);
  if (f == nullptr) return nullptr;
  f->vectorcall = public_call_detail::call;
  f->kind = kind;
  f->general = Py_NewRef(general);
  f->extra = Py_NewRef(extra);
  f->bound = Py_XNewRef(bound);
  f->dict = nullptr;
  f->last_handle = f->last_model = f->last_frames = nullptr;
  for (int i = 0; i < PUBLIC_CALL_MAX_ARGS; ++i) f->names[i] = nullptr;
  PyObject* self = reinterpret_cast<PyObject*>(f);
  for (int i = 0; i < kind->nparams; ++i) {
    f->names[i] = PyUnicode_InternFromString(kind->names[i]);
    if (f->names[i] == nullptr) {
      Py_DECREF(self);
      return nullptr;
    }
  }
  PyObject_GC_Track(self);
  return self;
}

}  // namespace fdcore

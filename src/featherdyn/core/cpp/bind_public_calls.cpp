// The public functions' one-state calls finished in C (public_calls.hpp; docs/architecture.md, "The public
// layer"): the kinds of the hand-written fast paths, and the declared algorithms' generic one (declared_path).
#include <cstring>
#include <string>

#include "declarations.hpp"
#include "frames.hpp"
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
    // object.__new__(cls) and its four fields set as a frozen dataclass's __init__ sets them (object.__setattr__
    // finds each slot's descriptor and calls its __set__): here the descriptors' own tp_descr_set, the
    // descriptors looked up once by `make` (extra[2:6])
    PyTypeObject* cls = reinterpret_cast<PyTypeObject*>(PyTuple_GET_ITEM(f->extra, 1));
    nb::object x = nb::steal(PyType_GenericNew(cls, nullptr, nullptr));
    if (!x.is_valid()) throw nb::python_error();
    PyObject* fields[4] = {R.ptr(), p.ptr(), Py_None, Py_None};
    for (int i = 0; i < 4; ++i) {
      PyObject* d = PyTuple_GET_ITEM(f->extra, 2 + i);
      if (Py_TYPE(d)->tp_descr_set(d, x.ptr(), fields[i]) != 0) throw nb::python_error();
    }
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

// The gravity flag (absent: True; exactly True or False, anything else declines).
bool flag_arg(PyObject* x, bool& out) {
  out = x == nullptr || x == Py_True;
  return x == nullptr || x == Py_True || x == Py_False;
}

// The core's Model a compiled model's method is bound to (f->bound).
const ModelData& bound_model(const PublicCall* f) { return *nb::inst_ptr<ModelData>(nb::handle(f->bound)); }

}  // namespace pc
}  // namespace

// fd.<name>(model, *inputs, ...) of a declared algorithm (extra = (CoreHandle, its Kernel, LOCAL, WORLD,
// LOCAL_WORLD_ALIGNED)), or fd.compile's method (*inputs, ...) bound to the core's Model (extra = (its Kernel, the
// frame table, LOCAL, WORLD, LOCAL_WORLD_ALIGNED)): its arguments where the Kernel's slots say — a frame by name or
// index, a reference by identity with the enums; out= absent: run_fresh, else run_into the given array (a tuple
// of them for several outputs).
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
  PyObject* out = a[at.out];
  if (out == nullptr || out == Py_None) return run_fresh(k, md->view, a + at.inputs, opt);
  PyObject* outs[DECLARED_MAX] = {out};
  const Py_ssize_t no = static_cast<Py_ssize_t>(k.outputs.size());
  if (no > 1) {
    if (!PyTuple_CheckExact(out) || PyTuple_GET_SIZE(out) != no) return nullptr;
    for (Py_ssize_t o = 0; o < no; ++o) outs[o] = PyTuple_GET_ITEM(out, o);
  }
  return run_into(k, md->view, a + at.inputs, outs, opt) == OK ? Py_NewRef(out) : nullptr;
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
    {"frame_placement", {{"model", "q", "frame"}, 3, 3, 3, frame_placement_path}, 6},
    {"fk", {{"q", "out"}, 2, 2, 1, fk_path}, 0},
    // a compiled model's methods (bound to the core's Model)
};

nb::object make(const std::string& kind, nb::handle general, nb::handle extra, nb::handle bound) {
  const NamedKind* named = nullptr;
  for (const NamedKind& n : KINDS)
    if (kind == n.name) named = &n;
  if (named == nullptr) throw nb::value_error("public_call: unknown kind");
  const PublicCallKind* k = &named->kind;
  const bool FK = kind == "fk", FRAME_PLACEMENT = kind == "frame_placement";
  const std::size_t need = named->constants;
  if (!PyTuple_Check(extra.ptr()) || static_cast<std::size_t>(PyTuple_GET_SIZE(extra.ptr())) != need)
    throw nb::value_error("public_call: wrong constants for this kind");
  const bool is_bound = FK;  // a compiled model's method
  if (is_bound && !nb::isinstance<ModelData>(bound))
    throw nb::type_error("public_call: a compiled model's method needs the core's Model");
  if (FRAME_PLACEMENT) {
    // the class and the names of four of its slots (data descriptors the class itself defines), which
    // frame_placement_path sets through the descriptors: extra becomes (CoreHandle, cls, the four descriptors)
    nb::handle cls = PyTuple_GET_ITEM(extra.ptr(), 1);
    nb::list with_descriptors;
    with_descriptors.append(nb::handle(PyTuple_GET_ITEM(extra.ptr(), 0)));
    with_descriptors.append(cls);
    if (!PyType_Check(cls.ptr())) throw nb::type_error("public_call: a class expected");
    for (int i = 2; i < 6; ++i) {
      nb::handle name = PyTuple_GET_ITEM(extra.ptr(), i);
      if (!PyUnicode_CheckExact(name.ptr()) || !nb::hasattr(cls, name)) throw nb::type_error("public_call: slot names expected");
      nb::object d = cls.attr(name);
      if (!PyDescr_IsData(d.ptr()) || Py_TYPE(d.ptr())->tp_descr_set == nullptr || !nb::hasattr(d, "__objclass__") ||
          !d.attr("__objclass__").is(cls))
        throw nb::type_error("public_call: slot names expected");
      with_descriptors.append(d);
    }
    nb::object constants = nb::steal(PyList_AsTuple(with_descriptors.ptr()));
    if (!constants.is_valid()) throw nb::python_error();
    PyObject* r = make_public_call(k, general.ptr(), constants.ptr(), nullptr);
    if (r == nullptr) throw nb::python_error();
    return nb::steal(r);
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

}  // namespace

void fdcore::bind_public_calls(nb::module_& m) {
  m.def("declared_call", [](const Kernel& k, nb::handle general, nb::handle extra, nb::handle bound) {
          const bool is_bound = !bound.is_none();
          if (!PyTuple_Check(extra.ptr()) || PyTuple_GET_SIZE(extra.ptr()) != 5 ||
              !nb::isinstance<Kernel>(nb::handle(PyTuple_GET_ITEM(extra.ptr(), is_bound ? 0 : 1))) ||
              nb::inst_ptr<Kernel>(nb::handle(PyTuple_GET_ITEM(extra.ptr(), is_bound ? 0 : 1))) != &k ||
              (is_bound && !PyDict_CheckExact(PyTuple_GET_ITEM(extra.ptr(), 1))))
            throw nb::value_error("declared_call: extra must be (CoreHandle, kernel, LOCAL, WORLD, LOCAL_WORLD_ALIGNED), "
                                  "or (kernel, frame table, LOCAL, WORLD, LOCAL_WORLD_ALIGNED) when bound");
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
  pc::init();
}

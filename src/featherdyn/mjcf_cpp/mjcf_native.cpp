// featherdyn._mjcf_native: the MJCF loader's fast path (docs/architecture.md, "MJCF models", "The fast path").
//
// read(text, strict, files) reads the usual MJCF document — plain XML, its includes, bodies, joints, geoms,
// inertials, sites, frames, default classes — into the body list featherdyn.mjcf builds its model from, with
// the Python loader's arithmetic operation for operation (same results bit for bit). Files are left to the
// Python loader's own functions, called back (included files, mesh files, mass properties and their cache).
// Anything else it *declines*: it returns None and the Python loader reads the document (<replicate>, shells,
// fullinertia, boundinertia, balanceinertia, every error and its message). So this file never words an error
// and never accepts what the Python loader refuses: where in doubt, it declines.
//
// The XML it reads is a strict subset of XML 1.0 (declined otherwise): ASCII outside comments; an optional
// XML declaration first; elements, attributes in quotes, comments, white space and text inside the root (read
// over); no DTD, entity or character reference, CDATA, processing instruction or namespace. Attribute values
// are normalised as XML requires (CR LF, CR, LF and tab each become one space).

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <deque>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

namespace {

using std::string_view;

struct Decline {};  // thrown for anything the fast path does not take

[[noreturn]] void decline() { throw Decline{}; }

// ---------------------------------------------------------------------------------------------------------------
// limits shared with the Python reader (featherdyn._urdf_xml, featherdyn.urdf); set at import
// ---------------------------------------------------------------------------------------------------------------

Py_ssize_t max_depth = 1000;            // _urdf_xml.MAX_DEPTH: deepest nesting of elements
constexpr size_t MAX_ELEMENTS = 1000000;  // most elements read (a larger document: the Python reader)
Py_ssize_t max_attribute_length = 10000;  // _urdf_xml.MAX_ATTRIBUTE_LENGTH
double max_length = 1e60;              // urdf.MAX_LENGTH
double max_mass = 1e100;               // urdf.MAX_MASS
double max_inertia = 1e100;            // urdf.MAX_INERTIA
PyObject* py_hypot = nullptr;          // math.hypot: its n-argument norm, called where the Python loader calls it

Py_ssize_t max_include_depth = 20;     // _mjcf_xml.MAX_INCLUDE_DEPTH
Py_ssize_t max_includes = 1000;        // _mjcf_xml.MAX_INCLUDES

constexpr double MJ_MINVAL = 1e-15;

// ---------------------------------------------------------------------------------------------------------------
// the XML subset
// ---------------------------------------------------------------------------------------------------------------

struct Attr {
  string_view name, value;
};

struct Elem {
  string_view tag;
  int attr_begin = 0, attr_end = 0;  // in Doc::attrs
  int first_child = -1, next_sibling = -1;
  int parent = -1;

  template <class F>
  void each_child(const std::vector<Elem>& all, F f) const {
    for (int c = first_child; c >= 0; c = all[c].next_sibling) f(c);
  }
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool name_start(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool name_char(char c) { return name_start(c) || (c >= '0' && c <= '9') || c == '.' || c == '-'; }

class Xml {
 public:
  std::vector<Elem> elems;
  std::vector<Attr> attrs;

  // Parse one text (the main file's, then each included file's) into elems and attrs; its root's index. The
  // text must outlive the Xml (the names and values are views of it).
  int parse(string_view text) {
    s_ = text;
    i_ = 0;
    int root = static_cast<int>(elems.size());
    parse_elements();
    return root;
  }

  const Elem& operator[](int i) const { return elems[i]; }

  // the element's own attribute, or nullptr
  const string_view* get(int e, string_view name) const {
    const Elem& el = elems[e];
    for (int k = el.attr_begin; k < el.attr_end; ++k)
      if (attrs[k].name == name) return &attrs[k].value;
    return nullptr;
  }

 private:
  string_view s_;
  size_t i_ = 0;
  std::deque<std::string> normalised_;  // attribute values with white space replaced (stable addresses)

  bool at(string_view w) const { return s_.substr(i_, w.size()) == w; }
  void skip_space() {
    while (i_ < s_.size() && is_space(s_[i_])) ++i_;
  }
  // white space and comments between elements
  void skip_misc() {
    for (;;) {
      skip_space();
      if (at("<!--")) {
        comment();
      } else {
        return;
      }
    }
  }
  void comment() {
    i_ += 4;
    for (;;) {
      if (i_ + 1 >= s_.size()) decline();
      char c = s_[i_];
      if (c == '-' && s_[i_ + 1] == '-') {  // "--" only as the end "-->"
        if (i_ + 2 < s_.size() && s_[i_ + 2] == '>') {
          i_ += 3;
          return;
        }
        decline();
      }
      auto u = static_cast<unsigned char>(c);
      if (u < 0x20 && !is_space(c)) decline();
      // U+FFFE and U+FFFF are not XML characters (UTF-8 EF BF BE / EF BF BF)
      if (u == 0xEF && i_ + 2 < s_.size() && static_cast<unsigned char>(s_[i_ + 1]) == 0xBF &&
          (static_cast<unsigned char>(s_[i_ + 2]) & 0xFE) == 0xBE)
        decline();
      ++i_;
    }
  }
  // character data up to the next '<': no reference, no control character, no "]]>"
  void text() {
    for (; i_ < s_.size() && s_[i_] != '<'; ++i_) {
      char c = s_[i_];
      auto u = static_cast<unsigned char>(c);
      if (c == '&' || (u < 0x20 && !is_space(c))) decline();
      if (c == '>' && i_ >= 2 && s_[i_ - 1] == ']' && s_[i_ - 2] == ']') decline();
    }
  }
  string_view name() {
    size_t b = i_;
    if (i_ >= s_.size() || !name_start(s_[i_])) decline();
    while (i_ < s_.size() && name_char(s_[i_])) ++i_;
    return s_.substr(b, i_ - b);
  }
  string_view quoted() {
    if (i_ >= s_.size() || (s_[i_] != '"' && s_[i_] != '\'')) decline();
    char q = s_[i_++];
    size_t b = i_;
    bool spaces = false;
    for (;;) {
      if (i_ >= s_.size()) decline();
      char c = s_[i_];
      if (c == q) break;
      auto u = static_cast<unsigned char>(c);
      if (c == '<' || c == '&' || u >= 0x80 || (u < 0x20 && !is_space(c))) decline();
      if (c == '\t' || c == '\n' || c == '\r') spaces = true;
      ++i_;
    }
    string_view raw = s_.substr(b, i_ - b);
    ++i_;
    if (static_cast<Py_ssize_t>(raw.size()) > max_attribute_length) decline();
    if (!spaces) return raw;
    std::string out;
    out.reserve(raw.size());
    for (size_t k = 0; k < raw.size(); ++k) {
      char c = raw[k];
      if (c == '\r' && k + 1 < raw.size() && raw[k + 1] == '\n') ++k;  // CR LF: one line end
      out.push_back(is_space(c) ? ' ' : c);
    }
    normalised_.push_back(std::move(out));
    return normalised_.back();
  }
  void declaration() {  // <?xml version="1.0" (encoding="...")? (standalone="yes|no")? ?>
    i_ += 5;
    std::vector<std::pair<string_view, string_view>> got;
    for (;;) {
      size_t before = i_;
      skip_space();
      if (at("?>")) {
        i_ += 2;
        break;
      }
      if (i_ == before) decline();
      string_view n = name();
      skip_space();
      if (i_ >= s_.size() || s_[i_] != '=') decline();
      ++i_;
      skip_space();
      got.emplace_back(n, quoted());
    }
    if (got.empty() || got.size() > 3 || got[0].first != "version" || got[0].second != "1.0") decline();
    size_t k = 1;
    if (k < got.size() && got[k].first == "encoding") {
      string_view e = got[k].second;
      if (e.empty() || !((e[0] >= 'A' && e[0] <= 'Z') || (e[0] >= 'a' && e[0] <= 'z'))) decline();
      for (char c : e)
        if (!(name_char(c))) decline();
      ++k;
    }
    if (k < got.size() && got[k].first == "standalone") {
      if (got[k].second != "yes" && got[k].second != "no") decline();
      ++k;
    }
    if (k != got.size()) decline();
  }

  void parse_elements() {
    if (at("<?xml") && i_ + 5 < s_.size() && is_space(s_[i_ + 5])) declaration();
    skip_misc();
    if (i_ >= s_.size() || s_[i_] != '<') decline();
    // the open elements, each with its last child (to link the next sibling)
    std::vector<std::pair<int, int>> open;
    for (;;) {
      // at '<' of a start tag
      ++i_;
      int e = static_cast<int>(elems.size());
      if (elems.size() >= MAX_ELEMENTS || static_cast<Py_ssize_t>(open.size()) + 1 >= max_depth) decline();
      elems.emplace_back();
      elems[e].tag = name();
      elems[e].attr_begin = static_cast<int>(attrs.size());
      bool empty = false;
      for (;;) {
        size_t before = i_;
        skip_space();
        if (i_ >= s_.size()) decline();
        if (s_[i_] == '>') {
          ++i_;
          break;
        }
        if (s_[i_] == '/') {
          if (i_ + 1 >= s_.size() || s_[i_ + 1] != '>') decline();
          i_ += 2;
          empty = true;
          break;
        }
        if (i_ == before) decline();  // attributes are separated by white space
        string_view n = name();
        if (n.substr(0, 5) == "xmlns") decline();
        skip_space();
        if (i_ >= s_.size() || s_[i_] != '=') decline();
        ++i_;
        skip_space();
        string_view v = quoted();
        for (int k = elems[e].attr_begin; k < static_cast<int>(attrs.size()); ++k)
          if (attrs[k].name == n) decline();  // a repeated attribute
        attrs.push_back({n, v});
      }
      elems[e].attr_end = static_cast<int>(attrs.size());
      if (!open.empty()) {
        auto& [parent, last] = open.back();
        elems[e].parent = parent;
        if (last < 0) {
          elems[parent].first_child = e;
        } else {
          elems[last].next_sibling = e;
        }
        last = e;
      }
      if (!empty) open.emplace_back(e, -1);
      // content: white space, comments, end tags, until the next start tag or the document's end
      for (;;) {
        if (open.empty()) {
          skip_misc();
          if (i_ != s_.size()) decline();
          return;
        }
        skip_misc();
        if (i_ >= s_.size()) decline();  // the end without closing
        if (s_[i_] != '<') {  // text (a stray ">" after a tag, say): read over, as the Python reader ignores it
          text();
          continue;
        }
        if (i_ + 1 < s_.size() && s_[i_ + 1] == '/') {
          i_ += 2;
          string_view n = name();
          skip_space();
          if (i_ >= s_.size() || s_[i_] != '>') decline();
          ++i_;
          if (n != elems[open.back().first].tag) decline();
          open.pop_back();
          continue;
        }
        if (i_ + 1 < s_.size() && name_start(s_[i_ + 1])) break;  // the next start tag
        decline();  // <! or <? (DTD, CDATA, processing instruction)
      }
    }
  }
};

// ---------------------------------------------------------------------------------------------------------------
// numbers: the Python reader's Doc.floats
// ---------------------------------------------------------------------------------------------------------------

// a decimal of the grammar [+-]?(d+(.d*)?|.d+)([eE][+-]?d+)?, converted correctly rounded (as Python's float)
double decimal(string_view t) {
  size_t k = 0, n = t.size();
  if (k < n && (t[k] == '+' || t[k] == '-')) ++k;
  size_t digits = 0;
  while (k < n && t[k] >= '0' && t[k] <= '9') ++k, ++digits;
  if (k < n && t[k] == '.') {
    ++k;
    while (k < n && t[k] >= '0' && t[k] <= '9') ++k, ++digits;
  }
  if (digits == 0) decline();
  if (k < n && (t[k] == 'e' || t[k] == 'E')) {
    ++k;
    if (k < n && (t[k] == '+' || t[k] == '-')) ++k;
    size_t e = 0;
    while (k < n && t[k] >= '0' && t[k] <= '9') ++k, ++e;
    if (e == 0) decline();
  }
  if (k != n) decline();
  const char* first = t.data() + (t[0] == '+' ? 1 : 0);
  double x = 0.0;
  auto [ptr, ec] = std::from_chars(first, t.data() + n, x);
  if (ec != std::errc() || ptr != t.data() + n || !std::isfinite(x)) decline();  // overflow, underflow: Python's
  return x;
}

// A parsed number list; zero: the Python reader's Z3 constant ("0 0 0" without a minus sign).
struct Numbers {
  double v[6];
  int n = 0;
  bool zero = false;
};

// The attribute's numbers when given (as many as one of the counts, each magnitude at most bound); false when
// absent or blank (MuJoCo's "not given"); anything else declines.
bool numbers(const string_view* text, std::initializer_list<int> counts, double bound, Numbers& out) {
  if (text == nullptr) return false;
  string_view t = *text;
  out.n = 0;
  size_t k = 0;
  while (k < t.size()) {
    while (k < t.size() && t[k] == ' ') ++k;
    if (k >= t.size()) break;
    size_t b = k;
    while (k < t.size() && t[k] != ' ') ++k;
    if (out.n == 6) decline();
    out.v[out.n++] = decimal(t.substr(b, k - b));
  }
  if (out.n == 0) return false;
  if (std::find(counts.begin(), counts.end(), out.n) == counts.end()) decline();
  for (int j = 0; j < out.n; ++j)
    if (!(std::fabs(out.v[j]) <= bound)) decline();
  out.zero = out.n == 3 && out.v[0] == 0.0 && out.v[1] == 0.0 && out.v[2] == 0.0 && t.find('-') == string_view::npos;
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
// 3×3 matrices and 3-vectors: featherdyn._mjcf_xml's tuple functions, with its identity shortcuts (I3, Z3)
// ---------------------------------------------------------------------------------------------------------------

struct M3 {
  double a[9];
  bool I;  // the constant I3
};
struct V3 {
  double v[3];
  bool Z;  // the constant Z3
};

const M3 I3{{1, 0, 0, 0, 1, 0, 0, 0, 1}, true};
const V3 Z3{{0, 0, 0}, true};

M3 mat(double a0, double a1, double a2, double a3, double a4, double a5, double a6, double a7, double a8) {
  return M3{{a0, a1, a2, a3, a4, a5, a6, a7, a8}, false};
}
V3 vec(double x, double y, double z) { return V3{{x, y, z}, false}; }

M3 mat_mul(const M3& A, const M3& B) {
  if (A.I) return B;
  if (B.I) return A;
  const double* a = A.a;
  const double* b = B.a;
  return mat(a[0] * b[0] + a[1] * b[3] + a[2] * b[6], a[0] * b[1] + a[1] * b[4] + a[2] * b[7],
             a[0] * b[2] + a[1] * b[5] + a[2] * b[8], a[3] * b[0] + a[4] * b[3] + a[5] * b[6],
             a[3] * b[1] + a[4] * b[4] + a[5] * b[7], a[3] * b[2] + a[4] * b[5] + a[5] * b[8],
             a[6] * b[0] + a[7] * b[3] + a[8] * b[6], a[6] * b[1] + a[7] * b[4] + a[8] * b[7],
             a[6] * b[2] + a[7] * b[5] + a[8] * b[8]);
}

V3 mat_vec(const M3& A, const V3& v) {
  if (A.I || v.Z) return v;
  const double* a = A.a;
  double x = v.v[0], y = v.v[1], z = v.v[2];
  return vec(a[0] * x + a[1] * y + a[2] * z, a[3] * x + a[4] * y + a[5] * z, a[6] * x + a[7] * y + a[8] * z);
}

V3 vec_add(const V3& a, const V3& b) {
  if (b.Z) return a;
  if (a.Z) return b;
  return vec(a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]);
}

V3 cross(const V3& a, const V3& b) {
  return vec(a.v[1] * b.v[2] - a.v[2] * b.v[1], a.v[2] * b.v[0] - a.v[0] * b.v[2], a.v[0] * b.v[1] - a.v[1] * b.v[0]);
}

struct Pose {
  M3 R;
  V3 p;
};

Pose compose(const M3& R1, const V3& p1, const M3& R2, const V3& p2) {
  if (R1.I) return {R2, p1.Z ? p2 : vec_add(p2, p1)};
  return {mat_mul(R1, R2), vec_add(mat_vec(R1, p2), p1)};
}

M3 diagonal(double d0, double d1, double d2) { return mat(d0, 0.0, 0.0, 0.0, d1, 0.0, 0.0, 0.0, d2); }

M3 rotate_symmetric(const M3& R, const M3& S) {
  if (R.I) return S;
  const double* r = R.a;
  const double* s = S.a;
  double t0 = r[0] * s[0] + r[1] * s[1] + r[2] * s[2], t1 = r[0] * s[1] + r[1] * s[4] + r[2] * s[5],
         t2 = r[0] * s[2] + r[1] * s[5] + r[2] * s[8];
  double t3 = r[3] * s[0] + r[4] * s[1] + r[5] * s[2], t4 = r[3] * s[1] + r[4] * s[4] + r[5] * s[5],
         t5 = r[3] * s[2] + r[4] * s[5] + r[5] * s[8];
  double t6 = r[6] * s[0] + r[7] * s[1] + r[8] * s[2], t7 = r[6] * s[1] + r[7] * s[4] + r[8] * s[5],
         t8 = r[6] * s[2] + r[7] * s[5] + r[8] * s[8];
  double xx = t0 * r[0] + t1 * r[1] + t2 * r[2], xy = t0 * r[3] + t1 * r[4] + t2 * r[5],
         xz = t0 * r[6] + t1 * r[7] + t2 * r[8];
  double yy = t3 * r[3] + t4 * r[4] + t5 * r[5], yz = t3 * r[6] + t4 * r[7] + t5 * r[8];
  double zz = t6 * r[6] + t7 * r[7] + t8 * r[8];
  return mat(xx, xy, xz, xy, yy, yz, xz, yz, zz);
}

M3 rotate_diagonal(const M3& R, double d0, double d1, double d2) {
  if (R.I) return diagonal(d0, d1, d2);
  const double* r = R.a;
  double a0 = r[0] * d0, a1 = r[1] * d1, a2 = r[2] * d2;
  double b0 = r[3] * d0, b1 = r[4] * d1, b2 = r[5] * d2;
  double xx = a0 * r[0] + a1 * r[1] + a2 * r[2], xy = a0 * r[3] + a1 * r[4] + a2 * r[5],
         xz = a0 * r[6] + a1 * r[7] + a2 * r[8];
  double yy = b0 * r[3] + b1 * r[4] + b2 * r[5], yz = b0 * r[6] + b1 * r[7] + b2 * r[8];
  double zz = r[6] * d0 * r[6] + r[7] * d1 * r[7] + r[8] * d2 * r[8];
  return mat(xx, xy, xz, xy, yy, yz, xz, yz, zz);
}

// math.hypot(*v), Python's n-argument norm (the Python loader's rounding)
double hypot_py(std::initializer_list<double> v) {
  PyObject* args[4] = {nullptr, nullptr, nullptr, nullptr};
  size_t n = 0;
  for (double x : v) {
    args[n] = PyFloat_FromDouble(x);
    if (args[n] == nullptr) {
      for (size_t k = 0; k < n; ++k) Py_DECREF(args[k]);
      throw Decline{};
    }
    ++n;
  }
  PyObject* r = PyObject_Vectorcall(py_hypot, args, n, nullptr);
  for (size_t k = 0; k < n; ++k) Py_DECREF(args[k]);
  if (r == nullptr) {
    PyErr_Clear();
    decline();
  }
  double out = PyFloat_AsDouble(r);
  Py_DECREF(r);
  return out;
}

M3 axis_angle_matrix(const double* axis, double angle) {
  if (angle == 0.0) return I3;
  double x = axis[0], y = axis[1], z = axis[2];
  double c = std::cos(angle), s = std::sin(angle);
  double t = 1 - c;
  return mat(t * x * x + c, t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c, t * y * z - s * x,
             t * x * z - s * y, t * y * z + s * x, t * z * z + c);
}

M3 z_to_vector(const V3& v) {
  double s = hypot_py({v.v[0], v.v[1]});
  if (s < 1e-14) return v.v[2] > 0 ? I3 : mat(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
  double axis[3] = {-v.v[1] / s, v.v[0] / s, 0.0};
  return axis_angle_matrix(axis, std::atan2(s, v.v[2]));
}

// ---------------------------------------------------------------------------------------------------------------
// the document: default classes, attributes over them, orientations (featherdyn._mjcf_xml.Doc)
// ---------------------------------------------------------------------------------------------------------------

enum Kind { K_JOINT, K_GEOM, K_SITE, K_FRAME, K_TENDON, K_INERTIAL, K_MESH, N_KINDS };

int kind_of(string_view tag) {
  if (tag == "joint") return K_JOINT;
  if (tag == "geom") return K_GEOM;
  if (tag == "site") return K_SITE;
  if (tag == "frame") return K_FRAME;
  if (tag == "tendon") return K_TENDON;
  if (tag == "inertial") return K_INERTIAL;
  if (tag == "mesh") return K_MESH;
  return -1;
}

bool replacing(string_view k) {  // an orientation or fromto: given on an element, it replaces all of its class's
  return k == "quat" || k == "axisangle" || k == "euler" || k == "xyaxes" || k == "zaxis" || k == "fromto";
}

using AttrList = std::vector<Attr>;

void overlay(AttrList& base, const Attr* b, const Attr* e) {  // _mjcf_xml._overlay
  bool replaces = false;
  for (const Attr* a = b; a != e; ++a) replaces |= replacing(a->name);
  if (replaces)
    base.erase(std::remove_if(base.begin(), base.end(), [](const Attr& a) { return replacing(a.name); }), base.end());
  for (const Attr* a = b; a != e; ++a) {
    auto it = std::find_if(base.begin(), base.end(), [&](const Attr& x) { return x.name == a->name; });
    if (it != base.end()) {
      it->value = a->value;
    } else {
      base.push_back(*a);
    }
  }
}

// An element's attributes over its class's: the lookup of Doc.attrs' merged dictionary.
struct Attrs {
  const Xml* xml;
  int elem;
  const AttrList* defaults;  // nullptr: none (a body, an inertial, a free joint)

  const string_view* get(string_view name) const {
    const string_view* own = xml->get(elem, name);
    const string_view* dflt = nullptr;
    if (defaults != nullptr)
      for (const Attr& a : *defaults)
        if (a.name == name) dflt = &a.value;
    if (own != nullptr) {
      // measured: an empty number is not read, the class's value stays (not so for an orientation)
      if (own->empty() && dflt != nullptr && !replacing(name)) return dflt;
      return own;
    }
    if (dflt != nullptr && replacing(name)) {  // an orientation given on the element replaces the class's
      const Elem& el = (*xml)[elem];
      for (int k = el.attr_begin; k < el.attr_end; ++k)
        if (replacing(xml->attrs[k].name)) return nullptr;
    }
    return dflt;
  }
  bool has(string_view name) const { return get(name) != nullptr; }
};

bool given_value(const string_view* t) {
  if (t == nullptr || t->empty()) return false;
  for (char c : *t)
    if (c != ' ') return true;
  return false;
}

struct Doc {
  const Xml& xml;
  bool degree = true;
  char eulerseq[3] = {'x', 'y', 'z'};
  std::unordered_map<string_view, int> class_id;
  std::vector<int> class_parent;
  std::vector<std::array<AttrList, N_KINDS>> own;
  std::vector<std::array<AttrList, N_KINDS>> resolved;
  std::vector<std::array<bool, N_KINDS>> done;

  explicit Doc(const Xml& x) : xml(x) { add_class("main", -1); }

  int add_class(string_view name, int parent) {
    if (class_id.count(name)) decline();  // defined twice: the Python reader's message
    int id = static_cast<int>(class_parent.size());
    class_id.emplace(name, id);
    class_parent.push_back(parent);
    own.emplace_back();
    resolved.emplace_back();
    done.emplace_back();
    return id;
  }

  const AttrList& defaults(int cls, int kind) {
    if (!done[cls][kind]) {
      std::vector<int> chain;
      for (int c = cls; c >= 0; c = class_parent[c]) chain.push_back(c);
      AttrList merged;
      for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        const AttrList& o = own[*it][kind];
        overlay(merged, o.data(), o.data() + o.size());
      }
      resolved[cls][kind] = std::move(merged);
      done[cls][kind] = true;
    }
    return resolved[cls][kind];
  }

  Attrs attrs(int e, int kind, int cls) { return Attrs{&xml, e, &defaults(cls, kind)}; }
  Attrs own_attrs(int e) const { return Attrs{&xml, e, nullptr}; }

  // Doc.element_class: the element's `attr` (class or childclass), else the enclosing childclass
  int element_class(int e, int childclass, string_view attr = "class") const {
    const string_view* c = xml.get(e, attr);
    if (c == nullptr) return childclass;
    auto it = class_id.find(*c);
    if (it == class_id.end()) decline();
    return it->second;
  }

  double angle(double x) const { return degree ? x * (M_PI / 180.0) : x; }  // math.radians

  // Doc.floats of a vector attribute: three numbers or the default (a Z3 from "0 0 0")
  V3 vector(const Attrs& a, string_view name, const V3& dflt, double bound = max_length) const {
    Numbers n;
    if (!numbers(a.get(name), {3}, bound, n)) return dflt;
    return V3{{n.v[0], n.v[1], n.v[2]}, n.zero};
  }
  double number(const Attrs& a, string_view name, double dflt, double bound = max_length) const {
    Numbers n;
    if (!numbers(a.get(name), {1}, bound, n)) return dflt;
    return n.v[0];
  }
  Numbers require(const Attrs& a, string_view name, int count) const {
    Numbers n;
    if (!numbers(a.get(name), {count}, max_length, n)) decline();
    return n;
  }
  bool boolean(const Attrs& a, string_view name, bool dflt) const {
    const string_view* t = a.get(name);
    if (t == nullptr) return dflt;
    if (*t == "true") return true;
    if (*t == "false") return false;
    decline();
  }

  V3 direction(double x, double y, double z) const {  // Doc._direction
    double n = hypot_py({x, y, z});
    if (n == 1.0) return vec(x, y, z);
    if (n < 1e-10) decline();
    return vec(x / n, y / n, z / n);
  }

  M3 rotation(const Attrs& a) const {  // Doc.rotation
    static const string_view kinds[] = {"quat", "axisangle", "euler", "xyaxes", "zaxis"};
    int given = -1, count = 0;
    for (int k = 0; k < 5; ++k)
      if (a.has(kinds[k])) given = count++ == 0 ? k : given;
    if (count == 0) return I3;
    if (count > 1) decline();
    if (!given_value(a.get(kinds[given]))) return I3;
    if (given == 0) {
      Numbers q = require(a, "quat", 4);
      double n = hypot_py({q.v[0], q.v[1], q.v[2], q.v[3]});
      if (n < 1e-10) decline();
      double w = q.v[0] / n, x = q.v[1] / n, y = q.v[2] / n, z = q.v[3] / n;
      return mat(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 2 * (x * y + z * w),
                 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 2 * (x * z - y * w), 2 * (y * z + x * w),
                 1 - 2 * (x * x + y * y));
    }
    if (given == 1) {
      Numbers aa = require(a, "axisangle", 4);
      V3 axis = direction(aa.v[0], aa.v[1], aa.v[2]);
      return axis_angle_matrix(axis.v, angle(aa.v[3]));
    }
    if (given == 2) {
      Numbers e = require(a, "euler", 3);
      M3 R = I3;
      for (int k = 0; k < 3; ++k) {
        char letter = eulerseq[k];
        bool lower = letter >= 'a';
        int axis_index = (lower ? letter - 'a' : letter - 'A') - ('x' - 'a');
        double axis[3] = {0.0, 0.0, 0.0};
        axis[axis_index] = 1.0;
        M3 Rk = axis_angle_matrix(axis, angle(e.v[k]));
        R = lower ? mat_mul(R, Rk) : mat_mul(Rk, R);
      }
      return R;
    }
    if (given == 3) {
      Numbers v = require(a, "xyaxes", 6);
      V3 ex = direction(v.v[0], v.v[1], v.v[2]);
      double d = ex.v[0] * v.v[3] + ex.v[1] * v.v[4] + ex.v[2] * v.v[5];
      V3 ey = direction(v.v[3] - ex.v[0] * d, v.v[4] - ex.v[1] * d, v.v[5] - ex.v[2] * d);
      V3 ez = cross(ex, ey);
      return mat(ex.v[0], ey.v[0], ez.v[0], ex.v[1], ey.v[1], ez.v[1], ex.v[2], ey.v[2], ez.v[2]);
    }
    Numbers z = require(a, "zaxis", 3);
    return z_to_vector(direction(z.v[0], z.v[1], z.v[2]));
  }

  Pose pose(const Attrs& a) const {  // Doc.pose
    V3 p = vector(a, "pos", Z3);
    return {rotation(a), p};
  }
};

// ---------------------------------------------------------------------------------------------------------------
// the loader (featherdyn.mjcf._Loader: read_top, read_bodies, read_content, read_joint, body_inertia)
// ---------------------------------------------------------------------------------------------------------------

struct Joint {
  string_view name;
  const char* kind;  // hinge, slide, ball, free
  bool freejoint_tag;
  V3 pos, axis;
  double ref, armature, lower, upper;
};

struct Geom {
  int elem, cls;
  Pose frame;
};

struct Site {
  string_view name;
  Pose pose;
};

struct Inertia {
  double m;
  V3 c;
  M3 ic;
};

struct Body {
  int elem;  // -1: the world
  string_view name;
  int parent;
  Pose pose;
  int childclass;
  std::vector<Joint> joints;
  std::vector<Geom> geoms;
  std::vector<Site> sites;
  int inertial = -1;
  Pose inertial_frame{I3, Z3};
  bool computed = false;  // the inertia below (moving bodies, or all with settotalmass)
  Inertia inertia{0.0, Z3, diagonal(0.0, 0.0, 0.0)};
};

const V3 Z_AXIS{{0.0, 0.0, 1.0}, false};

class Loader {
 public:
  Loader(Xml& xml, bool strict, PyObject* files) : xml_(xml), doc_(xml), strict_(strict), files_(files) {}
  Loader(const Loader&) = delete;
  Loader& operator=(const Loader&) = delete;
  ~Loader() {
    for (PyObject* t : texts_) Py_DECREF(t);
  }

  Xml& xml_;
  Doc doc_;
  bool strict_;
  PyObject* files_;  // the Python reader's file functions (mjcf._FastFiles), or nullptr: no files read
  std::vector<PyObject*> texts_;  // the included files' texts, alive while their views are
  std::vector<std::string> seen_;  // the files included (resolved paths)
  Py_ssize_t included_ = 0;
  // <compiler>
  std::string inertiafromgeom = "auto";
  long group_lo = 0, group_hi = 5;
  double boundmass = 0.0, settotalmass = -1.0;
  bool autolimits = true;
  const string_view* meshdir = nullptr;
  const string_view* assetdir = nullptr;
  // mesh assets by name; the mass properties of those read, per name: (V, c, I_c / rho)
  std::unordered_map<string_view, int> meshes;
  struct MeshProperties {
    double measure;
    double c[3];
    double J[9];
  };
  std::unordered_map<string_view, MeshProperties> mesh_cache;
  // <option>
  double gravity[3] = {0.0, 0.0, -9.81};
  bool gravity_disabled = false;
  std::vector<std::string> ignored;
  std::vector<Body> bodies;

  void ignore(const std::string& what) {
    if (strict_) decline();
    if (std::find(ignored.begin(), ignored.end(), what) == ignored.end()) ignored.push_back(what);
  }

  void read() {
    const Xml& x = xml_;
    if (x[0].tag != "mujoco") decline();
    expand_includes(0, static_cast<int>(x.elems.size()), 1);
    std::vector<int> tops;
    x[0].each_child(x.elems, [&](int c) { tops.push_back(c); });
    for (int c : tops) {
      string_view k = x[c].tag;
      if (k == "compiler") {
        read_compiler(c);
      } else if (k == "option") {
        read_option(c);
      } else if (k == "contact" || k == "equality" || k == "tendon" || k == "actuator" || k == "sensor" ||
                 k == "deformable" || k == "extension" || k == "plugin") {
        ignore(std::string(k));
      } else if (k == "body") {  // MuJoCo's schema takes it and its compiler ignores it
        ignore("body (outside <worldbody>)");
      } else if (k == "default" || k == "asset" || k == "worldbody" || k == "visual" || k == "statistic" ||
                 k == "size" || k == "custom" || k == "keyframe") {
      } else {
        decline();  // unknown elements: the Python reader
      }
    }
    read_defaults(tops);
    for (int c : tops)
      if (x[c].tag == "tendon") check_tendons(c);
    for (int c : tops)
      if (x[c].tag == "asset")
        x[c].each_child(x.elems, [&](int m) {
          if (x[m].tag == "mesh") read_mesh_asset(m);
        });
    // no <replicate> anywhere (the included files' elements too)
    std::vector<int> walk{0};
    while (!walk.empty()) {
      int e = walk.back();
      walk.pop_back();
      if (x[e].tag == "replicate") decline();
      x[e].each_child(x.elems, [&](int c) { walk.push_back(c); });
    }
    read_bodies(tops);
  }

  void read_compiler(int e) {
    Attrs a = doc_.own_attrs(e);
    if (const string_view* t = a.get("angle")) {
      if (*t == "degree") {
        doc_.degree = true;
      } else if (*t == "radian") {
        doc_.degree = false;
      } else {
        decline();
      }
    }
    if (const string_view* t = a.get("eulerseq")) {
      if (t->size() != 3) decline();
      for (int k = 0; k < 3; ++k) {
        char c = (*t)[k];
        if (std::strchr("xyzXYZ", c) == nullptr || c == 0) decline();
        doc_.eulerseq[k] = c;
      }
    }
    if (const string_view* t = a.get("coordinate"))
      if (*t != "local") decline();
    if (a.has("alignfree") && doc_.boolean(a, "alignfree", false)) decline();
    if (const string_view* t = a.get("inertiafromgeom")) {
      if (*t != "true" && *t != "false" && *t != "auto") decline();
      inertiafromgeom = std::string(*t);
    }
    if (a.has("inertiagrouprange")) {
      Numbers g;
      if (!numbers(a.get("inertiagrouprange"), {2}, max_length, g)) decline();
      for (int k = 0; k < 2; ++k)
        if (g.v[k] != std::trunc(g.v[k]) || std::fabs(g.v[k]) > 1e15) decline();
      group_lo = static_cast<long>(g.v[0]);
      group_hi = static_cast<long>(g.v[1]);
    }
    if (a.has("boundmass")) boundmass = doc_.number(a, "boundmass", 0.0, max_mass);
    if (a.has("boundinertia") && doc_.number(a, "boundinertia", 0.0, max_mass) > 0) decline();
    if (a.has("settotalmass")) settotalmass = doc_.number(a, "settotalmass", 0.0, max_mass);
    if (a.has("balanceinertia") && doc_.boolean(a, "balanceinertia", false)) decline();
    if (a.has("autolimits")) autolimits = doc_.boolean(a, "autolimits", true);
    if (const string_view* t = a.get("meshdir")) meshdir = t;
    if (const string_view* t = a.get("assetdir")) assetdir = t;
  }

  void read_option(int e) {
    Attrs a = doc_.own_attrs(e);
    Numbers g;
    if (numbers(a.get("gravity"), {3}, max_length, g)) std::copy(g.v, g.v + 3, gravity);
    xml_[e].each_child(xml_.elems, [&](int f) {
      if (xml_[f].tag == "flag") {
        const string_view* t = xml_.get(f, "gravity");
        if (t != nullptr && *t == "disable") gravity_disabled = true;
      }
    });
  }

  void read_defaults(const std::vector<int>& tops) {  // _mjcf_xml.read_defaults: one stack, the tops first
    std::vector<std::pair<int, int>> stack;
    for (int top : tops) {
      if (xml_[top].tag != "default") continue;
      const string_view* c = xml_.get(top, "class");
      if (c != nullptr && *c != "main") decline();
      stack.emplace_back(top, 0);
    }
    while (!stack.empty()) {
      auto [e, cls] = stack.back();
      stack.pop_back();
      xml_[e].each_child(xml_.elems, [&](int child) {
        string_view k = xml_[child].tag;
        if (k == "default") {
          const string_view* name = xml_.get(child, "class");
          if (name == nullptr || name->empty()) decline();
          stack.emplace_back(child, doc_.add_class(*name, cls));
          return;
        }
        int kind = kind_of(k);
        if (kind < 0) return;
        if (xml_.get(child, "class") != nullptr || xml_.get(child, "name") != nullptr) decline();
        const Elem& el = xml_[child];
        AttrList& table = doc_.own[cls][kind];
        overlay(table, xml_.attrs.data() + el.attr_begin, xml_.attrs.data() + el.attr_end);
      });
    }
  }

  void check_tendons(int e) {  // a tendon with armature: the Python reader refuses it
    xml_[e].each_child(xml_.elems, [&](int t) {
      string_view k = xml_[t].tag;
      if (k != "fixed" && k != "spatial") return;
      Attrs a = doc_.attrs(t, K_TENDON, doc_.element_class(t, 0));
      if (doc_.number(a, "armature", 0.0, max_mass) != 0) decline();
    });
  }

  void read_bodies(const std::vector<int>& tops) {
    bodies.push_back(Body{-1, "world", -1, {I3, Z3}, 0, {}, {}, {}});
    struct Pending {
      int elem, parent;
      Pose frame;
      int childclass;
    };
    std::vector<Pending> pending;
    for (int wb : tops)
      if (xml_[wb].tag == "worldbody") {
        std::vector<Pending> got;
        read_content(0, wb, 0, got);
        pending.insert(pending.end(), got.begin(), got.end());
      }
    std::reverse(pending.begin(), pending.end());
    while (!pending.empty()) {
      Pending it = pending.back();
      pending.pop_back();
      int cc = it.childclass;
      if (xml_.get(it.elem, "childclass") != nullptr) cc = doc_.element_class(it.elem, cc, "childclass");
      Pose pb = doc_.pose(doc_.own_attrs(it.elem));
      if (!it.frame.R.I || !it.frame.p.Z) pb = compose(it.frame.R, it.frame.p, pb.R, pb.p);
      const string_view* name = xml_.get(it.elem, "name");
      bodies.push_back(Body{it.elem, name ? *name : string_view(), it.parent, pb, cc, {}, {}, {}});
      std::vector<Pending> children;
      read_content(static_cast<int>(bodies.size()) - 1, it.elem, cc, children);
      pending.insert(pending.end(), children.rbegin(), children.rend());
      if (bodies.size() > 100000) decline();
    }
  }

  template <class P>
  void read_content(int b, int elem, int childclass, std::vector<P>& children) {
    struct Open {
      int next;  // the next child to read
      Pose frame;
      int cc;
    };
    std::vector<Open> open{{xml_[elem].first_child, {I3, Z3}, childclass}};
    while (!open.empty()) {
      Open& top = open.back();
      if (top.next < 0) {
        open.pop_back();
        continue;
      }
      int child = top.next;
      top.next = xml_[child].next_sibling;
      Pose frame = top.frame;
      int cc = top.cc;
      string_view k = xml_[child].tag;
      Body& body = bodies[b];
      if (k == "geom") {
        int cls = xml_.get(child, "class") == nullptr ? cc : doc_.element_class(child, cc);
        body.geoms.push_back(Geom{child, cls, frame});
      } else if (k == "body") {
        children.push_back(P{child, b, frame, cc});
      } else if (k == "frame") {
        int cls = doc_.element_class(child, cc);
        Pose f = doc_.pose(doc_.attrs(child, K_FRAME, cls));
        int sub = doc_.element_class(child, cc, "childclass");
        Pose composed = compose(frame.R, frame.p, f.R, f.p);
        open.push_back(Open{xml_[child].first_child, composed, sub});
      } else if (k == "site") {
        int cls = doc_.element_class(child, cc);
        Pose s = geom_pose(doc_.attrs(child, K_SITE, cls));
        const string_view* name = xml_.get(child, "name");
        body.sites.push_back(Site{name ? *name : string_view(), compose(frame.R, frame.p, s.R, s.p)});
      } else if (k == "joint" || k == "freejoint") {
        if (b == 0) decline();
        body.joints.push_back(read_joint(child, k == "freejoint", cc, frame));
      } else if (k == "inertial") {
        if (b == 0 || body.inertial >= 0) decline();
        body.inertial = child;
        body.inertial_frame = frame;
      } else if (k == "plugin") {
        ignore("plugin");
      } else if (k != "camera" && k != "light") {
        decline();  // composite, flexcomp, attach, unknown elements: the Python reader
      }
    }
  }

  // (z, middle, length) of a fromto segment; false without one
  bool fromto(const Attrs& a, V3& z, V3& middle, double& length) const {
    Numbers ft;
    if (!a.has("fromto") || !numbers(a.get("fromto"), {6}, max_length, ft)) return false;
    if (a.has("pos")) {
      Numbers pos;
      if (numbers(a.get("pos"), {3}, max_length, pos) && (pos.v[0] != 0 || pos.v[1] != 0 || pos.v[2] != 0))
        decline();
    }
    double d0 = ft.v[0] - ft.v[3], d1 = ft.v[1] - ft.v[4], d2 = ft.v[2] - ft.v[5];
    double n = hypot_py({d0, d1, d2});
    if (n < 1e-10) decline();
    z = vec(d0 / n, d1 / n, d2 / n);
    middle = vec((ft.v[0] + ft.v[3]) / 2, (ft.v[1] + ft.v[4]) / 2, (ft.v[2] + ft.v[5]) / 2);
    length = n;
    return true;
  }

  Pose geom_pose(const Attrs& a) const {
    V3 z, middle;
    double length;
    if (!fromto(a, z, middle, length)) return doc_.pose(a);
    return {z_to_vector(z), middle};
  }

  Joint read_joint(int e, bool freejoint, int cc, const Pose& frame) {
    Attrs a = freejoint ? doc_.own_attrs(e)
                        : doc_.attrs(e, K_JOINT, xml_.get(e, "class") == nullptr ? cc : doc_.element_class(e, cc));
    const char* kind = "free";
    if (!freejoint) {
      const string_view* t = a.get("type");
      string_view type = t ? *t : "hinge";
      if (type == "hinge") {
        kind = "hinge";
      } else if (type == "slide") {
        kind = "slide";
      } else if (type == "ball") {
        kind = "ball";
      } else if (type != "free") {
        decline();
      }
    }
    bool line = kind[0] == 'h' || kind[0] == 's';
    V3 pos = doc_.vector(a, "pos", Z3);
    Numbers given;
    bool has_axis = numbers(a.get("axis"), {3}, max_length, given);
    V3 axis = has_axis ? V3{{given.v[0], given.v[1], given.v[2]}, given.zero} : Z_AXIS;
    if (has_axis && line) axis = doc_.direction(axis.v[0], axis.v[1], axis.v[2]);
    double ref = doc_.number(a, "ref", 0.0);
    double armature = doc_.number(a, "armature", 0.0, max_mass);
    if (armature < 0) decline();
    double lower = -INFINITY, upper = INFINITY;
    const string_view* lim = a.get("limited");
    string_view limited = lim ? *lim : "auto";
    if (limited != "true" && limited != "false" && limited != "auto") decline();
    bool has_range = given_value(a.get("range"));
    if (limited == "auto") {
      if (has_range && !autolimits) decline();
      limited = has_range ? "true" : "false";
    }
    if (limited == "true" && line) {
      Numbers r;
      if (!numbers(a.get("range"), {2}, max_length, r)) r.v[0] = r.v[1] = 0.0;
      lower = r.v[0];
      upper = r.v[1];
      if (!(lower < upper)) decline();
      if (kind[0] == 'h' && doc_.degree) {
        lower = lower * (M_PI / 180.0);
        upper = upper * (M_PI / 180.0);
      }
    }
    if (kind[0] == 'h') {
      if (ref != 0 && doc_.degree) ref = ref * (M_PI / 180.0);
    } else if (!line) {
      ref = 0.0;
    }
    const string_view* name = xml_.get(e, "name");
    if (!frame.R.I) {
      pos = mat_vec(frame.R, pos);
      axis = mat_vec(frame.R, axis);
    }
    V3 placed = kind[0] != 'f' ? vec_add(pos, frame.p) : pos;
    return Joint{name ? *name : string_view(), kind, freejoint, placed, axis, ref, armature, lower, upper};
  }

  // ---- mesh assets (read_top, mesh_properties) ----

  static PyObject* str_or_none(const string_view* t) {
    if (t == nullptr) return Py_NewRef(Py_None);
    return PyUnicode_FromStringAndSize(t->data(), static_cast<Py_ssize_t>(t->size()));
  }

  // a Python reader's file function called back (a method of files_); its result (a new reference), or decline
  // if it raised
  PyObject* call_method(const char* name, PyObject* args) {
    if (args == nullptr) throw Decline{};
    PyObject* f = PyObject_GetAttrString(files_, name);
    PyObject* r = f == nullptr ? nullptr : PyObject_CallObject(f, args);
    Py_XDECREF(f);
    Py_DECREF(args);
    if (r == nullptr) {
      PyErr_Clear();  // a file the Python reader refuses: it words why
      decline();
    }
    return r;
  }

  // ---- <include> (read_document): each replaced by its file's root's children, the files read by the Python
  // reader's function; a file included twice, a cycle, too deep or too many: the Python reader words why ----

  void expand_includes(int begin, int end, Py_ssize_t depth) {  // the elements [begin, end) of one file
    for (int e = begin; e < end; ++e) {
      if (xml_[e].tag != "include") continue;
      if (files_ == nullptr || xml_[e].first_child >= 0 || depth > max_include_depth ||
          ++included_ > max_includes)
        decline();
      const string_view* file = xml_.get(e, "file");
      if (!given_value(file)) decline();
      PyObject* r = call_method("include", Py_BuildValue("(N)", str_or_none(file)));
      PyObject* path = nullptr;
      PyObject* text = nullptr;
      if (!PyArg_ParseTuple(r, "UU", &path, &text)) {
        Py_DECREF(r);
        PyErr_Clear();
        decline();
      }
      Py_INCREF(text);
      texts_.push_back(text);  // (kept before anything else can decline)
      Py_ssize_t n = 0;
      const char* p = PyUnicode_AsUTF8AndSize(path, &n);
      std::string resolved = p != nullptr ? std::string(p, static_cast<size_t>(n)) : std::string();
      Py_DECREF(r);
      if (p == nullptr) {
        PyErr_Clear();
        decline();
      }
      PyObject* main = PyObject_GetAttrString(files_, "main");
      bool cycle = main == nullptr || (main != Py_None && (!PyUnicode_Check(main) ||
                                                            PyUnicode_CompareWithASCIIString(main, resolved.c_str()) == 0));
      Py_XDECREF(main);
      if (cycle || std::find(seen_.begin(), seen_.end(), resolved) != seen_.end()) {
        PyErr_Clear();
        decline();
      }
      seen_.push_back(resolved);
      if (!PyUnicode_IS_ASCII(text)) decline();
      const char* t = PyUnicode_AsUTF8AndSize(text, &n);
      if (t == nullptr) {
        PyErr_Clear();
        decline();
      }
      int sub = xml_.parse(string_view(t, static_cast<size_t>(n)));
      if (xml_[sub].tag != "mujoco" && xml_[sub].tag != "mujocoinclude") decline();
      expand_includes(sub, static_cast<int>(xml_.elems.size()), depth + 1);
      splice(e, sub);
    }
  }

  // the element e replaced in its parent by the children of sub
  void splice(int e, int sub) {
    std::vector<Elem>& el = xml_.elems;
    int parent = el[e].parent, after = el[e].next_sibling;
    int first = el[sub].first_child, last = -1;
    for (int c = first; c >= 0; c = el[c].next_sibling) {
      el[c].parent = parent;
      last = c;
    }
    int head = first >= 0 ? first : after;
    if (last >= 0) el[last].next_sibling = after;
    if (el[parent].first_child == e) {
      el[parent].first_child = head;
    } else {
      int prev = el[parent].first_child;
      while (el[prev].next_sibling != e) prev = el[prev].next_sibling;
      el[prev].next_sibling = head;
    }
  }

  // Path(file).stem of a plain relative or absolute path (anything unusual declines)
  static string_view stem(string_view file) {
    if (file.empty() || file.find("//") != string_view::npos || file.find("/./") != string_view::npos ||
        file.substr(0, 2) == "./" || file.back() == '/' ||
        (file.size() >= 2 && file.substr(file.size() - 2) == "/.") || file == "." || file == "..")
      decline();
    size_t slash = file.rfind('/');
    string_view name = slash == string_view::npos ? file : file.substr(slash + 1);
    if (name == "..") decline();
    size_t dot = name.rfind('.');
    if (dot != string_view::npos && dot > 0 && dot + 1 < name.size()) return name.substr(0, dot);
    return name;
  }

  void read_mesh_asset(int m) {
    if (files_ == nullptr) decline();
    const string_view* name = xml_.get(m, "name");
    const string_view* file = xml_.get(m, "file");
    string_view key = name != nullptr && !name->empty() ? *name : file != nullptr ? stem(*file) : string_view();
    if (!key.empty()) meshes[key] = m;
    if (file != nullptr) {  // MuJoCo reads every asset: a missing file is refused
      PyObject* r = call_method("mesh_exists", Py_BuildValue("(NNN)", str_or_none(file), str_or_none(meshdir),
                                                             str_or_none(assetdir)));
      int exists = PyObject_IsTrue(r);
      Py_DECREF(r);
      if (exists != 1) {
        PyErr_Clear();
        decline();
      }
    }
  }

  const MeshProperties& mesh_properties(const Attrs& geom) {
    const string_view* name = geom.get("mesh");
    if (name == nullptr) decline();
    auto found = meshes.find(*name);
    if (found == meshes.end()) decline();
    auto cached = mesh_cache.find(*name);
    if (cached != mesh_cache.end()) return cached->second;
    int m = found->second;
    Attrs a = doc_.attrs(m, K_MESH, doc_.element_class(m, 0));
    const string_view* mode = a.get("inertia");
    string_view how = mode != nullptr ? *mode : "legacy";
    if (how != "legacy" && how != "exact" && how != "convex" && how != "shell") decline();
    if (a.has("refpos") || a.has("refquat")) decline();
    Numbers sc;
    double scale[3] = {1.0, 1.0, 1.0};
    if (numbers(a.get("scale"), {3}, max_length, sc)) std::copy(sc.v, sc.v + 3, scale);
    PyObject* r = call_method("mesh_properties",
                              Py_BuildValue("(NNN(ddd)s#NN)", str_or_none(a.get("file")), str_or_none(meshdir),
                                     str_or_none(assetdir), scale[0], scale[1], scale[2], how.data(),
                                     static_cast<Py_ssize_t>(how.size()), str_or_none(a.get("vertex")),
                                     str_or_none(a.get("face"))));
    MeshProperties got{};
    int ok = PyArg_ParseTuple(r, "d(ddd)(ddddddddd)", &got.measure, &got.c[0], &got.c[1], &got.c[2], &got.J[0],
                              &got.J[1], &got.J[2], &got.J[3], &got.J[4], &got.J[5], &got.J[6], &got.J[7], &got.J[8]);
    Py_DECREF(r);
    if (!ok) {
      PyErr_Clear();
      decline();
    }
    return mesh_cache.emplace(*name, got).first->second;
  }

  // ---- inertia ----

  static bool solid(string_view type, const double* s, double& V, double J[3]) {  // _mjcf_inertia._solid
    const double pi = M_PI;
    if (type == "capsule") {
      double r = s[0], H = 2 * s[1];
      double Vc = pi * r * r * H, Vs = 4.0 / 3.0 * pi * std::pow(r, 3.0);
      double axial = Vc * r * r / 2 + Vs * 2 * r * r / 5;
      double lateral = Vc * (3 * r * r + H * H) / 12 + Vs * (2 * r * r / 5 + H * H / 4 + 3 * H * r / 8);
      V = Vc + Vs;
      J[0] = J[1] = lateral;
      J[2] = axial;
      return true;
    }
    if (type == "sphere") {
      double r = s[0];
      V = 4.0 / 3.0 * pi * std::pow(r, 3.0);
      double j = V * 2 / 5 * r * r;
      J[0] = J[1] = J[2] = j;
      return true;
    }
    if (type == "ellipsoid") {
      double a = s[0], b = s[1], c = s[2];
      V = 4.0 / 3.0 * pi * a * b * c;
      J[0] = V / 5 * (b * b + c * c);
      J[1] = V / 5 * (a * a + c * c);
      J[2] = V / 5 * (a * a + b * b);
      return true;
    }
    if (type == "cylinder") {
      double r = s[0], h = s[1];
      V = pi * r * r * 2 * h;
      double lateral = V * ((3 * r * r + 4 * h * h) / 12);
      J[0] = J[1] = lateral;
      J[2] = V * (r * r / 2);
      return true;
    }
    if (type == "box") {
      double a = s[0], b = s[1], c = s[2];
      V = 8 * a * b * c;
      J[0] = V / 3 * (b * b + c * c);
      J[1] = V / 3 * (a * a + c * c);
      J[2] = V / 3 * (a * a + b * b);
      return true;
    }
    return false;
  }

  static M3 axisymmetric(double lateral, double axial, const V3& z) {
    double k = axial - lateral;
    double x = z.v[0], y = z.v[1], w = z.v[2];
    double xy = k * x * y, xz = k * x * w, yz = k * y * w;
    return mat(lateral + k * x * x, xy, xz, xy, lateral + k * y * y, yz, xz, yz, lateral + k * w * w);
  }

  static M3 sum9(const M3& a, const M3& b) {
    M3 out = mat(0, 0, 0, 0, 0, 0, 0, 0, 0);
    for (int k = 0; k < 9; ++k) out.a[k] = a.a[k] + b.a[k];
    return out;
  }

  static M3 parallel(const M3& ic, double m, double x, double y, double z) {
    double xx = m * x * x, yy = m * y * y, zz = m * z * z;
    double xy = m * x * y, xz = m * x * z, yz = m * y * z;
    const double* i = ic.a;
    return mat(i[0] + yy + zz, i[1] - xy, i[2] - xz, i[3] - xy, i[4] + xx + zz, i[5] - yz, i[6] - xz, i[7] - yz,
               i[8] + xx + yy);
  }

  // Loader.geom_inertia: false when the geom adds nothing
  bool geom_inertia(const Geom& g, bool moving, Inertia& out) {
    Attrs a = doc_.attrs(g.elem, K_GEOM, g.cls);
    const string_view* t = a.get("type");
    string_view type = t ? *t : "sphere";
    int needed = type == "sphere" ? 1 : type == "capsule" || type == "cylinder" ? 2
                                   : type == "ellipsoid" || type == "box"      ? 3
                                                                                : 0;
    bool mesh = type == "mesh";
    if (needed == 0 && !mesh && type != "plane" && type != "hfield") decline();  // sdf, unknown: the Python reader
    double group = a.has("group") ? doc_.number(a, "group", 0.0) : 0.0;
    if (!(group_lo <= group && group <= group_hi)) return false;
    if (needed == 0 && !mesh) {
      if (moving) decline();
      return false;
    }
    double mass = 0.0;
    bool has_mass = given_value(a.get("mass"));
    if (has_mass) {
      mass = doc_.number(a, "mass", 0.0, max_mass);
      if (mass < 0) decline();
      if (mass == 0) return false;
    }
    double density = doc_.number(a, "density", 1000.0, max_mass);
    if (density < 0) decline();
    if (a.has("shellinertia") && doc_.boolean(a, "shellinertia", false)) decline();  // shells: the Python reader
    if (mesh) {
      if (a.has("shellinertia")) decline();  // (set on the mesh asset instead)
      const MeshProperties& got = mesh_properties(a);
      double m = has_mass ? mass : density * got.measure;
      Pose gp = doc_.pose(a);
      Pose placed = compose(g.frame.R, g.frame.p, gp.R, gp.p);
      double k = m / got.measure;
      M3 J = mat(0, 0, 0, 0, 0, 0, 0, 0, 0);
      for (int i = 0; i < 9; ++i) J.a[i] = got.J[i] * k;
      out = {m, vec_add(mat_vec(placed.R, vec(got.c[0], got.c[1], got.c[2])), placed.p), rotate_symmetric(placed.R, J)};
      return true;
    }
    Numbers sz;
    double size[3] = {0.0, 0.0, 0.0};
    if (numbers(a.get("size"), {1, 2, 3}, max_length, sz)) std::copy(sz.v, sz.v + sz.n, size);
    bool has_turn;
    M3 turn = I3;
    V3 zg, pg;
    if (given_value(a.get("fromto"))) {
      double length;
      if (!fromto(a, zg, pg, length)) decline();
      has_turn = false;
      if (type == "capsule" || type == "cylinder") {
        size[1] = length / 2;
        size[2] = 0.0;
      } else if (type == "box" || type == "ellipsoid") {
        size[1] = size[0];
        size[2] = length / 2;
      }
    } else {
      Pose p = doc_.pose(a);
      turn = p.R;
      pg = p.p;
      has_turn = true;
      zg = vec(turn.a[2], turn.a[5], turn.a[8]);
    }
    if (!(size[0] > 0 && (needed < 2 || size[1] > 0) && (needed < 3 || size[2] > 0))) decline();
    double V = 0.0, J[3] = {0.0, 0.0, 0.0};
    if (!solid(type, size, V, J)) decline();
    double k = has_mass ? mass / V : density;
    double m = has_mass ? mass : density * V;
    double p0 = J[0] * k, p1 = J[1] * k, p2 = J[2] * k;
    const M3& R = g.frame.R;
    V3 c = vec_add(R.I ? pg : mat_vec(R, pg), g.frame.p);
    if (type == "sphere") {
      out = {m, c, diagonal(p0, p1, p2)};
    } else if (needed == 2) {
      out = {m, c, axisymmetric(p0, p2, R.I ? zg : mat_vec(R, zg))};
    } else {
      out = {m, c, rotate_diagonal(mat_mul(R, has_turn ? turn : z_to_vector(zg)), p0, p1, p2)};
    }
    return true;
  }

  void body_inertia(Body& body, bool moving) {  // Loader.body_inertia
    bool use_geoms = inertiafromgeom == "true" || (inertiafromgeom == "auto" && body.inertial < 0);
    std::vector<Inertia> parts;
    if (use_geoms) {
      for (const Geom& g : body.geoms) {
        Inertia got;
        if (geom_inertia(g, moving, got)) parts.push_back(got);
      }
      if (parts.empty() && body.inertial >= 0) use_geoms = false;
    }
    double principal[3];
    bool have_principal = false;
    if (use_geoms && parts.size() == 1) {
      body.inertia = parts[0];
    } else if (use_geoms) {
      double total = 0.0, first[3] = {0.0, 0.0, 0.0};
      for (const Inertia& q : parts) {
        total += q.m;
        first[0] += q.m * q.c.v[0];
        first[1] += q.m * q.c.v[1];
        first[2] += q.m * q.c.v[2];
      }
      V3 com = total > 0 ? vec(first[0] / total, first[1] / total, first[2] / total) : Z3;
      M3 second = mat(0, 0, 0, 0, 0, 0, 0, 0, 0);
      for (const Inertia& q : parts)
        second = parallel(sum9(second, q.ic), q.m, q.c.v[0] - com.v[0], q.c.v[1] - com.v[1], q.c.v[2] - com.v[2]);
      body.inertia = {total, com, second};
    } else if (body.inertial >= 0) {
      Attrs a = doc_.own_attrs(body.inertial);
      Numbers pos, mass, diag;
      if (!numbers(a.get("pos"), {3}, max_length, pos)) decline();
      if (!numbers(a.get("mass"), {1}, max_mass, mass) || mass.v[0] < 0) decline();
      if (!numbers(a.get("diaginertia"), {3}, max_mass, diag)) decline();
      if (a.has("fullinertia")) decline();  // (its eigenvalues: the Python reader)
      M3 tensor = diagonal(diag.v[0], diag.v[1], diag.v[2]);
      M3 Ri = doc_.rotation(a);
      std::copy(diag.v, diag.v + 3, principal);
      std::sort(principal, principal + 3);
      have_principal = true;
      double scale = std::max({std::fabs(principal[0]), std::fabs(principal[2]), MJ_MINVAL});
      if (principal[0] < -1e-12 * scale) decline();
      const Pose& f = body.inertial_frame;
      body.inertia = {mass.v[0], vec_add(mat_vec(f.R, vec(pos.v[0], pos.v[1], pos.v[2])), f.p),
                      rotate_symmetric(mat_mul(f.R, Ri), tensor)};
    }
    if (boundmass > 0 && body.inertia.m < boundmass) body.inertia.m = boundmass;
    double largest = 0.0;
    for (double x : body.inertia.ic.a) largest = std::max(largest, std::fabs(x));
    double m = body.inertia.m;
    if (!(std::isfinite(m) && std::isfinite(largest)) || m > max_mass || largest > max_inertia) decline();
    if (body.inertial >= 0 && !use_geoms) {
      if (!have_principal) decline();
      if (principal[0] + principal[1] < principal[2] * (1 - 1e-10) - MJ_MINVAL) decline();
    }
    body.computed = true;
  }

  void inertias() {
    size_t nb = bodies.size();
    std::vector<char> moving(nb, 0);
    for (size_t b = 1; b < nb; ++b) {
      moving[b] = !bodies[b].joints.empty() || moving[bodies[b].parent];
      if (moving[b] || settotalmass > 0) body_inertia(bodies[b], moving[b]);
    }
  }
};

// ---------------------------------------------------------------------------------------------------------------
// the result, for featherdyn.mjcf (None for the constants I3 and Z3)
// ---------------------------------------------------------------------------------------------------------------

struct Ref {  // an owned reference, released unless taken
  PyObject* p;
  explicit Ref(PyObject* o) : p(o) {
    if (p == nullptr) throw Decline{};
  }
  Ref(const Ref&) = delete;
  Ref& operator=(const Ref&) = delete;
  ~Ref() { Py_XDECREF(p); }
  PyObject* take() {
    PyObject* o = p;
    p = nullptr;
    return o;
  }
};

PyObject* str_of(string_view s) { return PyUnicode_FromStringAndSize(s.data(), static_cast<Py_ssize_t>(s.size())); }

PyObject* floats_of(const double* v, int n) {
  PyObject* t = PyTuple_New(n);
  if (t == nullptr) return nullptr;
  for (int k = 0; k < n; ++k) {
    PyObject* x = PyFloat_FromDouble(v[k]);
    if (x == nullptr) {
      Py_DECREF(t);
      return nullptr;
    }
    PyTuple_SET_ITEM(t, k, x);
  }
  return t;
}

PyObject* mat_of(const M3& R) {
  if (R.I) Py_RETURN_NONE;
  return floats_of(R.a, 9);
}
PyObject* vec_of(const V3& v) {
  if (v.Z) Py_RETURN_NONE;
  return floats_of(v.v, 3);
}

PyObject* result(const Loader& L) {
  Ref bodies(PyList_New(0));
  for (const Body& b : L.bodies) {
    Ref joints(PyList_New(0));
    for (const Joint& j : b.joints) {
      Ref t(Py_BuildValue("(NsNNNdddd)", str_of(j.name), j.kind, PyBool_FromLong(j.freejoint_tag), vec_of(j.pos),
                          vec_of(j.axis), j.ref, j.armature, j.lower, j.upper));
      if (PyList_Append(joints.p, t.p) < 0) throw Decline{};
    }
    Ref sites(PyList_New(0));
    for (const Site& s : b.sites) {
      Ref t(Py_BuildValue("(NNN)", str_of(s.name), mat_of(s.pose.R), vec_of(s.pose.p)));
      if (PyList_Append(sites.p, t.p) < 0) throw Decline{};
    }
    PyObject* inertia = b.computed
                            ? Py_BuildValue("(dNN)", b.inertia.m, vec_of(b.inertia.c), floats_of(b.inertia.ic.a, 9))
                            : Py_NewRef(Py_None);
    Ref t(Py_BuildValue("(NiNNNNN)", str_of(b.name), b.parent, mat_of(b.pose.R), vec_of(b.pose.p), joints.take(),
                        sites.take(), inertia));
    if (PyList_Append(bodies.p, t.p) < 0) throw Decline{};
  }
  Ref ignored(PyList_New(0));
  for (const std::string& s : L.ignored) {
    Ref u(PyUnicode_FromStringAndSize(s.data(), static_cast<Py_ssize_t>(s.size())));
    if (PyList_Append(ignored.p, u.p) < 0) throw Decline{};
  }
  const string_view* model = L.xml_.get(0, "model");
  PyObject* name = model != nullptr && !model->empty() ? str_of(*model) : Py_NewRef(Py_None);
  return Py_BuildValue("(N(ddd)ONdN)", name, L.gravity[0], L.gravity[1], L.gravity[2],
                       L.gravity_disabled ? Py_True : Py_False, ignored.take(), L.settotalmass, bodies.take());
}

PyObject* read(PyObject*, PyObject* const* args, Py_ssize_t nargs) {
  if ((nargs != 2 && nargs != 3) || !PyUnicode_Check(args[0])) {
    PyErr_SetString(PyExc_TypeError, "read(text: str, strict: bool[, files])");
    return nullptr;
  }
  PyObject* files = nargs == 3 && args[2] != Py_None ? args[2] : nullptr;  // without: a mesh or an include declines
  int strict = PyObject_IsTrue(args[1]);
  if (strict < 0) return nullptr;
  if (!PyUnicode_IS_ASCII(args[0])) {  // (comments with other characters: the Python reader)
    Py_RETURN_NONE;
  }
  Py_ssize_t n = 0;
  const char* s = PyUnicode_AsUTF8AndSize(args[0], &n);
  if (s == nullptr) return nullptr;
  try {
    Xml xml;
    xml.parse(string_view(s, static_cast<size_t>(n)));
    Loader loader(xml, strict != 0, files);
    loader.read();
    loader.inertias();
    return result(loader);
  } catch (const Decline&) {
    if (PyErr_Occurred()) return nullptr;  // (a failed allocation: MemoryError)
    Py_RETURN_NONE;
  } catch (const std::bad_alloc&) {
    return PyErr_NoMemory();
  }
}

PyObject* configure(PyObject*, PyObject* const* args, Py_ssize_t nargs) {
  if (nargs != 8) {
    PyErr_SetString(PyExc_TypeError, "configure(max_depth, max_attribute_length, max_length, max_mass, "
                                     "max_inertia, hypot, max_include_depth, max_includes)");
    return nullptr;
  }
  Py_ssize_t e = PyLong_AsSsize_t(args[0]), a = PyLong_AsSsize_t(args[1]);
  double l = PyFloat_AsDouble(args[2]), m = PyFloat_AsDouble(args[3]), i = PyFloat_AsDouble(args[4]);
  Py_ssize_t d = PyLong_AsSsize_t(args[6]), c = PyLong_AsSsize_t(args[7]);
  if (PyErr_Occurred()) return nullptr;
  if (!PyCallable_Check(args[5])) {
    PyErr_SetString(PyExc_TypeError, "configure: hypot must be callable");
    return nullptr;
  }
  max_depth = e;
  max_attribute_length = a;
  max_length = l;
  max_mass = m;
  max_inertia = i;
  max_include_depth = d;
  max_includes = c;
  Py_XSETREF(py_hypot, Py_NewRef(args[5]));
  Py_RETURN_NONE;
}

PyMethodDef methods[] = {
    {"read", reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(read)), METH_FASTCALL,
     "read(text, strict[, files]) -> the body list of a usual MJCF document, or None (declined: the Python reader "
     "reads it); files: the Python reader's file functions (mesh_exists, mesh_properties, include, main)"},
    {"configure", reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(configure)), METH_FASTCALL,
     "configure(max_depth, max_attribute_length, max_length, max_mass, max_inertia, hypot, max_include_depth, "
     "max_includes): the Python reader's limits"},
    {nullptr, nullptr, 0, nullptr}};

PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "_mjcf_native",
                          "The MJCF loader's fast path (featherdyn.mjcf; docs/architecture.md).", -1, methods,
                          nullptr, nullptr, nullptr, nullptr};

}  // namespace

PyMODINIT_FUNC PyInit__mjcf_native() { return PyModule_Create(&module_def); }

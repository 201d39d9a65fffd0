// SPDX-License-Identifier: MIT
// 3MF reader: ZIP container (zip_archive.h, inflate.h), model part located through the package
// relationships, XML scanned just enough for the core mesh schema: <object><mesh><vertices>
// <vertex x y z/>, <triangles><triangle v1 v2 v3/>, <components><component objectid transform/>,
// <build><item objectid transform/>, and the unit attribute of <model>. Objects are emitted once
// per build item with the composed transforms, in millimetres.
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/parse_number.h"
#include "mesh/read_formats.h"
#include "mesh/zip_archive.h"

namespace omnislice {
namespace {

// 3MF affine transform "m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32": a row vector
// [x y z 1] times the 4x3 matrix, so x' = x*m00 + y*m10 + z*m20 + m30.
struct Transform {
  double m[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};

  void apply(const double* p, double* out) const {
    for (int c = 0; c < 3; ++c) out[c] = p[0] * m[c] + p[1] * m[3 + c] + p[2] * m[6 + c] + m[9 + c];
  }
  // The transform applying *this first, then outer (matrix product this * outer).
  Transform then(const Transform& outer) const {
    Transform t;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 3; ++c) {
        double v = m[3 * r] * outer.m[c] + m[3 * r + 1] * outer.m[3 + c] + m[3 * r + 2] * outer.m[6 + c];
        if (r == 3) v += outer.m[9 + c];
        t.m[3 * r + c] = v;
      }
    }
    return t;
  }
};

struct Component {
  std::string path;  // model part holding the object; empty = the same part
  int64_t objectId = 0;
  Transform transform;
};

struct Object {
  bool hasMesh = false;
  std::vector<double> positions;
  std::vector<uint32_t> triangles;
  std::vector<Component> components;
};

struct ModelPart {
  double unitScale = 1.0;  // model units to millimetres
  std::string unit = "millimeter";
  std::map<int64_t, Object> objects;
  std::vector<Component> items;  // build items
  bool hasBuild = false;
};

struct XmlAttr {
  std::string_view name;   // local name (prefix removed)
  std::string_view value;  // raw, entities not decoded
};

std::string_view localName(std::string_view qname) {
  const size_t colon = qname.rfind(':');
  return colon == std::string_view::npos ? qname : qname.substr(colon + 1);
}

inline bool xmlSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// Pull scanner for the XML subset 3MF uses: elements with attributes; text, comments,
// processing instructions, CDATA and DOCTYPE are skipped. Checks that tags nest properly.
class XmlScanner {
 public:
  enum Kind { Start, End, Eof, Error };

  XmlScanner(const char* b, const char* e) : begin_(b), p_(b), end_(e) {
    if (e - b >= 3 && std::memcmp(b, "\xEF\xBB\xBF", 3) == 0) p_ += 3;  // UTF-8 byte order mark
  }

  Kind next() {
    if (pendingEnd_) {
      pendingEnd_ = false;
      stack_.pop_back();
      return End;
    }
    for (;;) {
      const char* lt = static_cast<const char*>(std::memchr(p_, '<', static_cast<size_t>(end_ - p_)));
      if (lt == nullptr) {
        p_ = end_;
        if (!stack_.empty()) return fail("file ends inside <" + std::string(stack_.back()) + ">");
        return Eof;
      }
      p_ = lt + 1;
      if (startsWith("!--")) {
        if (!skipPast("-->")) return fail("unterminated comment");
        continue;
      }
      if (startsWith("![CDATA[")) {
        if (!skipPast("]]>")) return fail("unterminated CDATA section");
        continue;
      }
      if (startsWith("?")) {
        if (!skipPast("?>")) return fail("unterminated processing instruction");
        continue;
      }
      if (startsWith("!")) {
        if (!skipPast(">")) return fail("unterminated declaration");
        continue;
      }
      if (startsWith("/")) {
        ++p_;
        const char* nb = p_;
        while (p_ != end_ && !xmlSpace(*p_) && *p_ != '>') ++p_;
        const std::string_view qname(nb, static_cast<size_t>(p_ - nb));
        while (p_ != end_ && xmlSpace(*p_)) ++p_;
        if (p_ == end_ || *p_ != '>') return fail("unterminated end tag");
        ++p_;
        if (stack_.empty() || stack_.back() != qname) {
          return fail("end tag </" + std::string(qname.substr(0, 40)) + "> does not match " +
                      (stack_.empty() ? std::string("any open element") : "<" + std::string(stack_.back()) + ">"));
        }
        name_ = localName(qname);
        stack_.pop_back();
        return End;
      }
      return startTag();
    }
  }

  std::string_view name() const { return name_; }
  const std::vector<XmlAttr>& attrs() const { return attrs_; }
  // Local name of the ancestor `up` levels above the current start tag (0 = its parent).
  std::string_view ancestor(size_t up) const {
    // The current element is on the stack top (also for self-closing tags until the End event).
    if (stack_.size() < up + 2) return {};
    return localName(stack_[stack_.size() - 2 - up]);
  }
  const std::string& error() const { return error_; }

 private:
  bool startsWith(const char* s) const {
    const size_t n = std::strlen(s);
    return static_cast<size_t>(end_ - p_) >= n && std::memcmp(p_, s, n) == 0;
  }
  bool skipPast(const char* s) {
    const size_t n = std::strlen(s);
    for (const char* q = p_; static_cast<size_t>(end_ - q) >= n; ++q) {
      q = static_cast<const char*>(std::memchr(q, s[0], static_cast<size_t>(end_ - q)));
      if (q == nullptr || static_cast<size_t>(end_ - q) < n) break;
      if (std::memcmp(q, s, n) == 0) {
        p_ = q + n;
        return true;
      }
    }
    p_ = end_;
    return false;
  }
  Kind fail(const std::string& what) {
    size_t line = 1;
    for (const char* q = begin_; q < p_ && q < end_; ++q) line += *q == '\n';
    error_ = "XML line " + std::to_string(line) + ": " + what;
    return Error;
  }

  Kind startTag() {
    const char* nb = p_;
    while (p_ != end_ && !xmlSpace(*p_) && *p_ != '>' && *p_ != '/') ++p_;
    if (p_ == nb) return fail("bad tag");
    const std::string_view qname(nb, static_cast<size_t>(p_ - nb));
    attrs_.clear();
    for (;;) {
      while (p_ != end_ && xmlSpace(*p_)) ++p_;
      if (p_ == end_) return fail("unterminated tag <" + std::string(qname.substr(0, 40)) + ">");
      if (*p_ == '>') {
        ++p_;
        break;
      }
      if (*p_ == '/') {
        if (end_ - p_ < 2 || p_[1] != '>') return fail("bad '/' in tag <" + std::string(qname.substr(0, 40)) + ">");
        p_ += 2;
        pendingEnd_ = true;
        break;
      }
      const char* ab = p_;
      while (p_ != end_ && !xmlSpace(*p_) && *p_ != '=' && *p_ != '>' && *p_ != '/') ++p_;
      const std::string_view aname(ab, static_cast<size_t>(p_ - ab));
      while (p_ != end_ && xmlSpace(*p_)) ++p_;
      if (aname.empty() || p_ == end_ || *p_ != '=') return fail("bad attribute in <" + std::string(qname.substr(0, 40)) + ">");
      ++p_;
      while (p_ != end_ && xmlSpace(*p_)) ++p_;
      if (p_ == end_ || (*p_ != '"' && *p_ != '\'')) return fail("unquoted attribute value in <" + std::string(qname.substr(0, 40)) + ">");
      const char quote = *p_++;
      const char* vb = p_;
      const char* ve = static_cast<const char*>(std::memchr(p_, quote, static_cast<size_t>(end_ - p_)));
      if (ve == nullptr) return fail("unterminated attribute value");
      p_ = ve + 1;
      attrs_.push_back({localName(aname), std::string_view(vb, static_cast<size_t>(ve - vb))});
    }
    stack_.push_back(qname);
    name_ = localName(qname);
    return Start;
  }

  const char* begin_;
  const char* p_;
  const char* end_;
  std::vector<std::string_view> stack_;
  std::vector<XmlAttr> attrs_;
  std::string_view name_;
  bool pendingEnd_ = false;
  std::string error_;
};

// Decodes the five predefined entities and numeric character references (ASCII range).
std::string decodeEntities(std::string_view v) {
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] != '&') {
      out += v[i];
      continue;
    }
    const size_t semi = v.find(';', i);
    if (semi == std::string_view::npos) {
      out += v[i];
      continue;
    }
    const std::string_view ent = v.substr(i + 1, semi - i - 1);
    if (ent == "amp") out += '&';
    else if (ent == "lt") out += '<';
    else if (ent == "gt") out += '>';
    else if (ent == "quot") out += '"';
    else if (ent == "apos") out += '\'';
    else if (ent.size() > 1 && ent[0] == '#') {
      const long code = ent[1] == 'x' ? std::strtol(std::string(ent.substr(2)).c_str(), nullptr, 16)
                                      : std::strtol(std::string(ent.substr(1)).c_str(), nullptr, 10);
      out += (code > 0 && code < 128) ? static_cast<char>(code) : '?';
    } else {
      out += '&';
      continue;
    }
    i = semi;
  }
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && xmlSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && xmlSpace(s.back())) s.remove_suffix(1);
  return s;
}

const std::string_view* findAttr(const std::vector<XmlAttr>& attrs, std::string_view name) {
  for (const XmlAttr& a : attrs) {
    if (a.name == name) return &a.value;
  }
  return nullptr;
}

bool attrDouble(const std::vector<XmlAttr>& attrs, std::string_view name, double& out) {
  const std::string_view* v = findAttr(attrs, name);
  if (v == nullptr) return false;
  const std::string_view t = trim(*v);
  return parseDouble(t.data(), t.data() + t.size(), out);
}

bool attrInt(const std::vector<XmlAttr>& attrs, std::string_view name, int64_t& out) {
  const std::string_view* v = findAttr(attrs, name);
  if (v == nullptr) return false;
  const std::string_view t = trim(*v);
  return parseInt64(t.data(), t.data() + t.size(), out);
}

bool parseTransform(std::string_view s, Transform& t) {
  size_t i = 0;
  for (int k = 0; k < 12; ++k) {
    while (i < s.size() && xmlSpace(s[i])) ++i;
    const size_t b = i;
    while (i < s.size() && !xmlSpace(s[i])) ++i;
    if (b == i || !parseDouble(s.data() + b, s.data() + i, t.m[k])) return false;
  }
  while (i < s.size() && xmlSpace(s[i])) ++i;
  return i == s.size();
}

// Part names are absolute ("/3D/3dmodel.model") in 3MF and relative in ZIP.
std::string partName(std::string_view target) {
  std::string s = decodeEntities(target);
  while (!s.empty() && s[0] == '/') s.erase(0, 1);
  return s;
}

bool equalsNoCase(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  }
  return true;
}

bool unitScale(const std::string& unit, double& scale) {
  static const std::pair<const char*, double> units[] = {{"micron", 0.001}, {"millimeter", 1.0}, {"centimeter", 10.0},
                                                         {"inch", 25.4},    {"foot", 304.8},     {"meter", 1000.0}};
  for (const auto& u : units) {
    if (unit == u.first) {
      scale = u.second;
      return true;
    }
  }
  return false;
}

class ThreeMfReader {
 public:
  ThreeMfReader(const uint8_t* data, size_t size, ReadMeshResult& r) : data_(data), size_(size), r_(r) {}

  bool run() {
    ZipDirectory dir = readZipDirectory(data_, size_);
    if (!dir.ok()) return fail(dir.status, "3MF: " + dir.message);
    entries_ = std::move(dir.entries);
    std::string rootName;
    if (!findRootModel(rootName)) return false;
    ModelPart* root = part(rootName);
    if (root == nullptr) return false;
    if (!unitScale(root->unit, scale_)) {
      r_.warnings.push_back("3MF: unknown unit '" + root->unit.substr(0, 40) + "', read as millimeter");
      scale_ = 1.0;
    }
    if (!root->hasBuild || root->items.empty()) {
      r_.warnings.push_back("3MF: no build items; every top-level object is used as placed");
      std::map<int64_t, bool> referenced;
      for (const auto& [id, obj] : root->objects) {
        for (const Component& c : obj.components) {
          if (c.path.empty() || equalsNoCase(c.path, rootName)) referenced[c.objectId] = true;
        }
      }
      for (const auto& [id, obj] : root->objects) {
        if (!referenced.count(id) && !emit(rootName, id, Transform(), 0)) return false;
      }
      return true;
    }
    const std::vector<Component> items = root->items;
    for (const Component& item : items) {
      if (!emit(item.path.empty() ? rootName : item.path, item.objectId, item.transform, 0)) return false;
    }
    return true;
  }

 private:
  bool fail(Status s, const std::string& message) {
    r_.status = s;
    r_.message = message;
    r_.mesh = Mesh();
    return false;
  }

  const ZipEntry* entry(const std::string& name) const {
    for (const ZipEntry& e : entries_) {
      if (e.name == name) return &e;
    }
    for (const ZipEntry& e : entries_) {
      if (equalsNoCase(e.name, name)) return &e;
    }
    return nullptr;
  }

  bool extract(const ZipEntry& e, std::vector<uint8_t>& out) {
    ZipExtractResult x = extractZipEntry(data_, size_, e);
    if (!x.ok()) return fail(x.status, "3MF: " + x.message);
    out = std::move(x.data);
    return true;
  }

  // The model part named by the package relationship of type .../3dmodel, else the usual name.
  bool findRootModel(std::string& name) {
    if (const ZipEntry* rels = entry("_rels/.rels")) {
      std::vector<uint8_t> xml;
      if (!extract(*rels, xml)) return false;
      const char* b = reinterpret_cast<const char*>(xml.data());
      XmlScanner s(b, b + xml.size());
      for (;;) {
        const XmlScanner::Kind k = s.next();
        if (k == XmlScanner::Error) return fail(Status::ParseError, "3MF _rels/.rels: " + s.error());
        if (k == XmlScanner::Eof) break;
        if (k != XmlScanner::Start || s.name() != "Relationship") continue;
        const std::string_view* type = findAttr(s.attrs(), "Type");
        const std::string_view* target = findAttr(s.attrs(), "Target");
        if (type && target && type->size() >= 8 && type->substr(type->size() - 8) == "/3dmodel") {
          name = partName(*target);
          if (entry(name) == nullptr) return fail(Status::ParseError, "3MF: relationship names a missing part '" + name.substr(0, 80) + "'");
          return true;
        }
      }
    }
    if (entry("3D/3dmodel.model") != nullptr) {
      name = "3D/3dmodel.model";
      return true;
    }
    for (const ZipEntry& e : entries_) {
      if (e.name.size() > 6 && equalsNoCase(e.name.substr(e.name.size() - 6), ".model")) {
        name = e.name;
        return true;
      }
    }
    return fail(Status::ParseError, "3MF: no 3D model part in the archive (" + std::to_string(entries_.size()) + " entries)");
  }

  // Parsed model part by name (cached), nullptr after fail().
  ModelPart* part(const std::string& rawName) {
    const std::string name = partName(rawName);
    for (auto& [n, p] : parts_) {
      if (equalsNoCase(n, name)) return p.get();
    }
    const ZipEntry* e = entry(name);
    if (e == nullptr) {
      fail(Status::ParseError, "3MF: missing model part '" + name.substr(0, 80) + "'");
      return nullptr;
    }
    std::vector<uint8_t> xml;
    if (!extract(*e, xml)) return nullptr;
    auto model = std::make_unique<ModelPart>();
    if (!parseModel(xml, name, *model)) return nullptr;
    parts_.emplace_back(name, std::move(model));
    return parts_.back().second.get();
  }

  bool parseModel(const std::vector<uint8_t>& xml, const std::string& name, ModelPart& model) {
    const char* b = reinterpret_cast<const char*>(xml.data());
    XmlScanner s(b, b + xml.size());
    const std::string where = "3MF " + name.substr(0, 80) + ": ";
    Object* obj = nullptr;
    int64_t objId = 0;
    bool sawModel = false;
    for (;;) {
      const XmlScanner::Kind k = s.next();
      if (k == XmlScanner::Error) return fail(Status::ParseError, where + s.error());
      if (k == XmlScanner::Eof) break;
      const std::string_view n = s.name();
      if (k == XmlScanner::End) {
        if (n == "object" && obj != nullptr) {
          const size_t nv = obj->positions.size() / 3;
          for (uint32_t v : obj->triangles) {
            if (v >= nv) {
              return fail(Status::ParseError, where + "object " + std::to_string(objId) + " triangle index " + std::to_string(v) +
                                                  " out of range (" + std::to_string(nv) + " vertices)");
            }
          }
          obj = nullptr;
        }
        continue;
      }
      const std::vector<XmlAttr>& a = s.attrs();
      if (n == "vertex" && obj != nullptr && s.ancestor(0) == "vertices" && s.ancestor(1) == "mesh") {
        double xyz[3];
        if (!attrDouble(a, "x", xyz[0]) || !attrDouble(a, "y", xyz[1]) || !attrDouble(a, "z", xyz[2])) {
          return fail(Status::ParseError, where + "object " + std::to_string(objId) + ": vertex without valid x, y, z");
        }
        pushXyz(obj->positions, xyz);
      } else if (n == "triangle" && obj != nullptr && s.ancestor(0) == "triangles" && s.ancestor(1) == "mesh") {
        int64_t v[3];
        if (!attrInt(a, "v1", v[0]) || !attrInt(a, "v2", v[1]) || !attrInt(a, "v3", v[2])) {
          return fail(Status::ParseError, where + "object " + std::to_string(objId) + ": triangle without valid v1, v2, v3");
        }
        for (int64_t x : v) {
          if (x < 0 || x > 0xFFFFFFFFll) {
            return fail(Status::ParseError, where + "object " + std::to_string(objId) + ": triangle index " + std::to_string(x) + " out of range");
          }
          obj->triangles.push_back(static_cast<uint32_t>(x));
        }
      } else if (n == "model" && s.ancestor(0).empty()) {
        sawModel = true;
        if (const std::string_view* u = findAttr(a, "unit")) model.unit = decodeEntities(trim(*u));
      } else if (n == "object" && s.ancestor(0) == "resources") {
        if (!attrInt(a, "id", objId)) return fail(Status::ParseError, where + "object without a valid id");
        if (model.objects.count(objId)) return fail(Status::ParseError, where + "duplicate object id " + std::to_string(objId));
        obj = &model.objects[objId];
      } else if (n == "mesh" && obj != nullptr && s.ancestor(0) == "object") {
        obj->hasMesh = true;
      } else if ((n == "component" && obj != nullptr && s.ancestor(0) == "components") ||
                 (n == "item" && s.ancestor(0) == "build")) {
        Component c;
        if (!attrInt(a, "objectid", c.objectId)) return fail(Status::ParseError, where + std::string(n) + " without a valid objectid");
        if (const std::string_view* t = findAttr(a, "transform")) {
          if (!parseTransform(*t, c.transform)) return fail(Status::ParseError, where + std::string(n) + " with a malformed transform");
        }
        if (const std::string_view* p = findAttr(a, "path")) c.path = partName(*p);
        if (n == "item") model.items.push_back(std::move(c));
        else obj->components.push_back(std::move(c));
      } else if (n == "build" && s.ancestor(0) == "model") {
        model.hasBuild = true;
      }
    }
    if (!sawModel) return fail(Status::ParseError, where + "no <model> root element");
    return true;
  }

  // Appends object `id` of part `partPath` under transform t (and its components, recursively).
  bool emit(const std::string& partPath, int64_t id, const Transform& t, int depth) {
    if (depth > 32) return fail(Status::ParseError, "3MF: components nested more than 32 deep");
    // Shared components may legitimately repeat, but a hostile file could multiply them.
    if (++emitted_ > 10000000) return fail(Status::ParseError, "3MF: more than 10 million object instances");
    ModelPart* p = part(partPath);
    if (p == nullptr) return false;
    const auto it = p->objects.find(id);
    if (it == p->objects.end()) return fail(Status::ParseError, "3MF: reference to unknown object " + std::to_string(id));
    const Object& obj = it->second;
    for (const Object* open : path_) {
      if (open == &obj) return fail(Status::ParseError, "3MF: object " + std::to_string(id) + " contains itself through components");
    }
    Mesh& m = r_.mesh;
    if (obj.hasMesh) {
      const size_t base = m.positions.size() / 3;
      if (base + obj.positions.size() / 3 > 0xFFFFFFFFull) return fail(Status::ParseError, "3MF: too many vertices");
      m.positions.resize(3 * base + obj.positions.size());
      for (size_t v = 0; v < obj.positions.size() / 3; ++v) {
        double world[3];
        t.apply(&obj.positions[3 * v], world);
        for (int c = 0; c < 3; ++c) m.positions[3 * (base + v) + c] = world[c] * scale_;
      }
      m.triangles.reserve(m.triangles.size() + obj.triangles.size());
      for (uint32_t v : obj.triangles) m.triangles.push_back(static_cast<uint32_t>(base + v));
    }
    // part() may parse another part and grow parts_, but each ModelPart (and obj) stays put.
    path_.push_back(&obj);
    for (const Component& c : obj.components) {
      if (!emit(c.path.empty() ? partPath : c.path, c.objectId, c.transform.then(t), depth + 1)) return false;
    }
    path_.pop_back();
    return true;
  }

  const uint8_t* data_;
  size_t size_;
  ReadMeshResult& r_;
  std::vector<ZipEntry> entries_;
  std::vector<std::pair<std::string, std::unique_ptr<ModelPart>>> parts_;
  double scale_ = 1.0;
  std::vector<const Object*> path_;  // objects being emitted, outermost first (cycle check)
  size_t emitted_ = 0;
};

}  // namespace

ReadMeshResult read3mf(const uint8_t* data, size_t size) {
  ReadMeshResult r;
  r.format = "3mf";
  ThreeMfReader reader(data, size, r);
  if (!reader.run()) r.mesh = Mesh();
  return r;
}

}  // namespace omnislice

// SPDX-License-Identifier: MIT
// PLY reader (ascii, binary_little_endian, binary_big_endian). Reads x,y,z of the "vertex"
// element and the "vertex_indices" / "vertex_index" list of the "face" element, whatever their
// types; every other property and element (lists included) is skipped by its declared layout.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "mesh/parse_number.h"
#include "mesh/read_formats.h"
#include "mesh/text_cursor.h"

namespace omnislice {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

size_t typeSize(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8: return 1;
    case PlyType::Int16:
    case PlyType::UInt16: return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 1;
}

bool isInteger(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

bool parseType(const std::string& s, PlyType& t) {
  struct Name {
    const char* name;
    PlyType type;
  };
  static const Name names[] = {{"char", PlyType::Int8},     {"int8", PlyType::Int8},      {"uchar", PlyType::UInt8},
                               {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},    {"int16", PlyType::Int16},
                               {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},  {"int", PlyType::Int32},
                               {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},    {"uint32", PlyType::UInt32},
                               {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
                               {"float64", PlyType::Float64}};
  for (const Name& n : names) {
    if (s == n.name) {
      t = n.type;
      return true;
    }
  }
  return false;
}

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyType countType = PlyType::UInt8;
  PlyType type = PlyType::Float32;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> props;
};

enum class PlyEncoding { Ascii, LittleEndian, BigEndian };

inline uint64_t loadUnsigned(const uint8_t* p, size_t n, bool bigEndian) {
  uint64_t v = 0;
  if (bigEndian) {
    for (size_t i = 0; i < n; ++i) v = v << 8 | p[i];
  } else {
    for (size_t i = n; i-- > 0;) v = v << 8 | p[i];
  }
  return v;
}

inline double loadDouble(PlyType t, const uint8_t* p, bool be) {
  const uint64_t u = loadUnsigned(p, typeSize(t), be);
  switch (t) {
    case PlyType::Int8: return static_cast<int8_t>(static_cast<uint8_t>(u));
    case PlyType::UInt8: return static_cast<double>(u);
    case PlyType::Int16: return static_cast<int16_t>(static_cast<uint16_t>(u));
    case PlyType::UInt16: return static_cast<double>(u);
    case PlyType::Int32: return static_cast<int32_t>(static_cast<uint32_t>(u));
    case PlyType::UInt32: return static_cast<double>(u);
    case PlyType::Float32: {
      const uint32_t bits = static_cast<uint32_t>(u);
      float f;
      std::memcpy(&f, &bits, sizeof f);
      return f;
    }
    case PlyType::Float64: {
      double d;
      std::memcpy(&d, &u, sizeof d);
      return d;
    }
  }
  return 0;
}

// Integer types only (checked when the header is read).
inline int64_t loadInteger(PlyType t, const uint8_t* p, bool be) {
  const uint64_t u = loadUnsigned(p, typeSize(t), be);
  switch (t) {
    case PlyType::Int8: return static_cast<int8_t>(static_cast<uint8_t>(u));
    case PlyType::Int16: return static_cast<int16_t>(static_cast<uint16_t>(u));
    case PlyType::Int32: return static_cast<int32_t>(static_cast<uint32_t>(u));
    default: return static_cast<int64_t>(u);
  }
}

struct Header {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  size_t dataOffset = 0;
};

std::vector<std::string> splitWords(const char* b, const char* e) {
  std::vector<std::string> words;
  while (b != e) {
    while (b != e && (*b == ' ' || *b == '\t' || *b == '\r')) ++b;
    const char* s = b;
    while (b != e && *b != ' ' && *b != '\t' && *b != '\r') ++b;
    if (s != b) words.emplace_back(s, b);
  }
  return words;
}

// Parses the header; on failure sets r.status / r.message and returns false.
bool readHeader(const uint8_t* data, size_t size, Header& h, ReadMeshResult& r) {
  const char* text = reinterpret_cast<const char*>(data);
  size_t pos = 0;
  size_t lineNo = 0;
  bool sawFormat = false;
  auto fail = [&r, &lineNo](Status s, const std::string& what) {
    r.status = s;
    r.message = "PLY header line " + std::to_string(lineNo) + ": " + what;
    return false;
  };
  for (;;) {
    ++lineNo;
    if (pos >= size) return fail(Status::TruncatedFile, "file ends before 'end_header'");
    const char* b = text + pos;
    const char* nl = static_cast<const char*>(std::memchr(b, '\n', size - pos));
    if (nl == nullptr) return fail(Status::TruncatedFile, "file ends before 'end_header'");
    pos = static_cast<size_t>(nl - text) + 1;
    const std::vector<std::string> w = splitWords(b, nl);
    if (lineNo == 1) {
      if (w.size() != 1 || w[0] != "ply") return fail(Status::ParseError, "missing 'ply' magic");
      continue;
    }
    if (w.empty()) continue;
    const std::string& key = w[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (w.size() < 2) return fail(Status::ParseError, "format without encoding");
      if (w[1] == "ascii") {
        h.encoding = PlyEncoding::Ascii;
      } else if (w[1] == "binary_little_endian") {
        h.encoding = PlyEncoding::LittleEndian;
      } else if (w[1] == "binary_big_endian") {
        h.encoding = PlyEncoding::BigEndian;
      } else {
        return fail(Status::ParseError, "unknown format '" + w[1].substr(0, 40) + "'");
      }
      sawFormat = true;
    } else if (key == "element") {
      if (w.size() != 3) return fail(Status::ParseError, "element needs a name and a count");
      PlyElement el;
      el.name = w[1];
      int64_t count;
      if (!parseInt64(w[2].data(), w[2].data() + w[2].size(), count) || count < 0) {
        return fail(Status::ParseError, "bad element count '" + w[2].substr(0, 40) + "'");
      }
      el.count = static_cast<uint64_t>(count);
      h.elements.push_back(std::move(el));
    } else if (key == "property") {
      if (h.elements.empty()) return fail(Status::ParseError, "property before any element");
      PlyProperty prop;
      if (w.size() == 5 && w[1] == "list") {
        prop.isList = true;
        if (!parseType(w[2], prop.countType) || !parseType(w[3], prop.type)) {
          return fail(Status::ParseError, "unknown list property type");
        }
        if (!isInteger(prop.countType)) return fail(Status::ParseError, "list count type must be an integer type");
        prop.name = w[4];
      } else if (w.size() == 3) {
        if (!parseType(w[1], prop.type)) return fail(Status::ParseError, "unknown property type '" + w[1].substr(0, 40) + "'");
        prop.name = w[2];
      } else {
        return fail(Status::ParseError, "malformed property line");
      }
      h.elements.back().props.push_back(std::move(prop));
    } else if (key == "end_header") {
      if (!sawFormat) return fail(Status::ParseError, "no format line");
      h.dataOffset = pos;
      return true;
    } else {
      // A keyword the standard does not define (exporters add their own, e.g. 'texturefile'
      // outside a comment): it describes no element, so the data still reads.
      r.warnings.push_back("PLY header line " + std::to_string(lineNo) + ": skipped the unknown keyword '" +
                           key.substr(0, 40) + "'");
    }
  }
}

// Roles of the properties that matter.
struct Roles {
  int x = -1, y = -1, z = -1;  // in the vertex element
  int indices = -1;            // list property in the face element
};

class PlyDataReader {
 public:
  PlyDataReader(const uint8_t* data, size_t size, const Header& h, ReadMeshResult& r)
      : data_(data), size_(size), h_(h), r_(r), be_(h.encoding == PlyEncoding::BigEndian) {}

  bool run() {
    for (const PlyElement& el : h_.elements) {
      if (el.name == "vertex") {
        vertexCount_ = el.count;
        break;
      }
    }
    if (vertexCount_ > 0xFFFFFFFFull) return fail(Status::ParseError, "vertex count too large for 32-bit indices");
    pos_ = h_.dataOffset;
    TextCursor cursor(data_ + pos_, size_ - pos_);
    cursor_ = &cursor;
    for (const PlyElement& el : h_.elements) {
      Roles roles;
      bool isVertex = el.name == "vertex";
      bool isFace = el.name == "face";
      for (size_t i = 0; i < el.props.size(); ++i) {
        const PlyProperty& p = el.props[i];
        if (isVertex && !p.isList) {
          if (p.name == "x") roles.x = static_cast<int>(i);
          if (p.name == "y") roles.y = static_cast<int>(i);
          if (p.name == "z") roles.z = static_cast<int>(i);
        }
        if (isFace && p.isList && (p.name == "vertex_indices" || p.name == "vertex_index") && roles.indices < 0) {
          if (!isInteger(p.type)) return fail(Status::ParseError, "face vertex_indices must have an integer type");
          roles.indices = static_cast<int>(i);
        }
      }
      if (isVertex && (roles.x < 0 || roles.y < 0 || roles.z < 0)) {
        return fail(Status::ParseError, "vertex element lacks x, y or z");
      }
      if (isFace && roles.indices < 0) return fail(Status::ParseError, "face element has no vertex_indices list");
      if (!isVertex && !isFace) roles = Roles();
      const bool ok = h_.encoding == PlyEncoding::Ascii ? readAsciiElement(el, roles, isVertex, isFace)
                                                        : readBinaryElement(el, roles, isVertex, isFace);
      if (!ok) return false;
    }
    if (h_.encoding == PlyEncoding::Ascii && !cursor.atEnd()) {
      r_.warnings.push_back("PLY: ignored data after the last element (line " + std::to_string(cursor.lineNumber()) + ")");
    } else if (h_.encoding != PlyEncoding::Ascii && pos_ < size_) {
      r_.warnings.push_back("PLY: ignored " + std::to_string(size_ - pos_) + " bytes after the last element");
    }
    if (skippedFaces_ > 0) r_.warnings.push_back("PLY: skipped " + std::to_string(skippedFaces_) + " faces with fewer than 3 vertices");
    return true;
  }

 private:
  bool fail(Status s, const std::string& what) {
    r_.status = s;
    r_.message = "PLY: " + what;
    return false;
  }

  bool truncated(const PlyElement& el, uint64_t item) {
    return fail(Status::TruncatedFile, "data ends in element '" + el.name.substr(0, 40) + "' item " + std::to_string(item) +
                                           " of " + std::to_string(el.count) + " declared");
  }

  void reserveFor(const PlyElement& el, bool isVertex, bool isFace) {
    const uint64_t cap = std::min<uint64_t>(el.count, (size_ - pos_) / 2 + 1);
    if (isVertex) r_.mesh.positions.reserve(3 * cap);
    if (isFace) r_.mesh.triangles.reserve(3 * cap);
  }

  bool emitPolygon(const PlyElement& el, uint64_t item) {
    for (int64_t idx : polygon_) {
      if (idx < 0 || static_cast<uint64_t>(idx) >= vertexCount_) {
        return fail(Status::ParseError, "face " + std::to_string(item) + " index " + std::to_string(idx) + " out of range (" +
                                            std::to_string(vertexCount_) + " vertices)");
      }
    }
    if (polygon_.size() < 3) {
      ++skippedFaces_;
      return true;
    }
    std::vector<uint32_t>& t = r_.mesh.triangles;
    for (size_t k = 1; k + 1 < polygon_.size(); ++k) {
      t.push_back(static_cast<uint32_t>(polygon_[0]));
      t.push_back(static_cast<uint32_t>(polygon_[k]));
      t.push_back(static_cast<uint32_t>(polygon_[k + 1]));
    }
    return true;
  }

  bool readBinaryElement(const PlyElement& el, const Roles& roles, bool isVertex, bool isFace) {
    bool fixed = true;
    size_t stride = 0;
    for (const PlyProperty& p : el.props) {
      if (p.isList) fixed = false;
      else stride += typeSize(p.type);
    }
    if (fixed) {
      // Fixed-size items: one bounds check for the whole element.
      if (stride != 0 && el.count > (size_ - pos_) / stride) return truncated(el, (size_ - pos_) / stride);
      if (isVertex) {
        size_t off[3] = {0, 0, 0};
        PlyType type[3];
        const int which[3] = {roles.x, roles.y, roles.z};
        for (int k = 0; k < 3; ++k) {
          for (int i = 0; i < which[k]; ++i) off[k] += typeSize(el.props[i].type);
          type[k] = el.props[which[k]].type;
        }
        std::vector<double>& out = r_.mesh.positions;
        out.resize(3 * el.count);
        const uint8_t* item = data_ + pos_;
        for (uint64_t i = 0; i < el.count; ++i, item += stride) {
          for (int k = 0; k < 3; ++k) out[3 * i + k] = loadDouble(type[k], item + off[k], be_);
        }
      }
      pos_ += el.count * stride;
      return true;
    }
    reserveFor(el, isVertex, isFace);
    double xyz[3] = {0, 0, 0};
    for (uint64_t i = 0; i < el.count; ++i) {
      for (size_t pi = 0; pi < el.props.size(); ++pi) {
        const PlyProperty& p = el.props[pi];
        const int ipi = static_cast<int>(pi);
        if (!p.isList) {
          const size_t n = typeSize(p.type);
          if (size_ - pos_ < n) return truncated(el, i);
          if (isVertex && (ipi == roles.x || ipi == roles.y || ipi == roles.z)) {
            xyz[ipi == roles.x ? 0 : ipi == roles.y ? 1 : 2] = loadDouble(p.type, data_ + pos_, be_);
          }
          pos_ += n;
          continue;
        }
        const size_t cn = typeSize(p.countType);
        if (size_ - pos_ < cn) return truncated(el, i);
        const int64_t count = loadInteger(p.countType, data_ + pos_, be_);
        pos_ += cn;
        if (count < 0) return fail(Status::ParseError, "negative list length in element '" + el.name.substr(0, 40) + "'");
        const size_t n = typeSize(p.type);
        if (static_cast<uint64_t>(count) > (size_ - pos_) / n) return truncated(el, i);
        if (isFace && ipi == roles.indices) {
          polygon_.clear();
          for (int64_t k = 0; k < count; ++k) polygon_.push_back(loadInteger(p.type, data_ + pos_ + k * n, be_));
          if (!emitPolygon(el, i)) return false;
        }
        pos_ += static_cast<size_t>(count) * n;
      }
      if (isVertex) pushXyz(r_.mesh.positions, xyz);
    }
    return true;
  }

  bool readAsciiElement(const PlyElement& el, const Roles& roles, bool isVertex, bool isFace) {
    if (el.props.empty()) return true;  // items without properties hold no data (any count)
    reserveFor(el, isVertex, isFace);
    TextCursor& c = *cursor_;
    const char* b;
    const char* e;
    double xyz[3] = {0, 0, 0};
    auto bad = [&](const char* what) {
      return fail(Status::ParseError, "line " + std::to_string(c.lineNumber()) + ": bad " + what + " " + tokenForMessage(b, e));
    };
    for (uint64_t i = 0; i < el.count; ++i) {
      for (size_t pi = 0; pi < el.props.size(); ++pi) {
        const PlyProperty& p = el.props[pi];
        const int ipi = static_cast<int>(pi);
        if (!c.next(b, e)) return truncated(el, i);
        if (!p.isList) {
          if (isVertex && (ipi == roles.x || ipi == roles.y || ipi == roles.z)) {
            double v;
            if (!parseDouble(b, e, v)) return bad("coordinate");
            xyz[ipi == roles.x ? 0 : ipi == roles.y ? 1 : 2] = v;
          }
          continue;
        }
        int64_t count;
        if (!parseInt64(b, e, count) || count < 0) return bad("list length");
        const bool wanted = isFace && ipi == roles.indices;
        if (wanted) polygon_.clear();
        for (int64_t k = 0; k < count; ++k) {
          if (!c.next(b, e)) return truncated(el, i);
          if (wanted) {
            int64_t idx;
            if (!parseInt64(b, e, idx)) return bad("vertex index");
            polygon_.push_back(idx);
          }
        }
        if (wanted && !emitPolygon(el, i)) return false;
      }
      if (isVertex) pushXyz(r_.mesh.positions, xyz);
    }
    return true;
  }

  const uint8_t* data_;
  size_t size_;
  const Header& h_;
  ReadMeshResult& r_;
  bool be_;
  size_t pos_ = 0;
  TextCursor* cursor_ = nullptr;
  uint64_t vertexCount_ = 0;
  std::vector<int64_t> polygon_;
  size_t skippedFaces_ = 0;
};

}  // namespace

ReadMeshResult readPly(const uint8_t* data, size_t size) {
  ReadMeshResult r;
  r.format = "ply";
  Header h;
  if (!readHeader(data, size, h, r)) return r;
  r.format = h.encoding == PlyEncoding::Ascii          ? "ply-ascii"
             : h.encoding == PlyEncoding::LittleEndian ? "ply-binary-le"
                                                       : "ply-binary-be";
  PlyDataReader reader(data, size, h, r);
  if (!reader.run()) r.mesh = Mesh();
  return r;
}

}  // namespace omnislice

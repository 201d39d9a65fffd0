// SPDX-License-Identifier: MIT
// Format choice and the common checks around the per-format readers (read_formats.h).
#include "mesh/read_mesh.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <system_error>

#include "common/memory_budget.h"
#include "mesh/read_formats.h"
#include "mesh/text_cursor.h"
#include "tet/tet_mesh.h"

namespace omnislice {
namespace {

enum class Format { Unknown, Stl, Obj, Off, Ply, ThreeMf, Tet };

const char* formatName(Format f) {
  switch (f) {
    case Format::Stl: return "STL";
    case Format::Obj: return "OBJ";
    case Format::Off: return "OFF";
    case Format::Ply: return "PLY";
    case Format::ThreeMf: return "3MF";
    case Format::Tet: return "TET";
    case Format::Unknown: break;
  }
  return "unknown";
}

Format formatFromName(const std::string& name) {
  const size_t slash = name.find_last_of("/\\");
  const size_t dot = name.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return Format::Unknown;
  std::string ext = name.substr(dot + 1);
  for (char& c : ext) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  if (ext == "stl") return Format::Stl;
  if (ext == "obj") return Format::Obj;
  if (ext == "off") return Format::Off;
  if (ext == "ply") return Format::Ply;
  if (ext == "3mf") return Format::ThreeMf;
  if (ext == "tet") return Format::Tet;
  return Format::Unknown;
}

bool hasBinaryByte(const uint8_t* data, size_t size) {
  for (size_t i = 0; i < size; ++i) {
    const uint8_t c = data[i];
    if (c < 32 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') return true;
  }
  return false;
}

// Content signatures that identify a format with confidence (they may override the extension).
Format strongSniff(const uint8_t* data, size_t size) {
  if (size >= 4 && std::memcmp(data, "PK\x03\x04", 4) == 0) return Format::ThreeMf;
  if (size >= 4 && std::memcmp(data, "ply", 3) == 0 && (data[3] == '\n' || data[3] == '\r')) return Format::Ply;
  if (looksLikeAsciiStl(data, size)) return Format::Stl;
  if (binaryStlSizeMatches(data, size) && hasBinaryByte(data, size)) return Format::Stl;
  // OFF: first token (after comments) is a header keyword ending in "OFF".
  TextCursor c(data, size < 4096 ? size : 4096);
  c.commentChar = '#';
  const char* b;
  const char* e;
  if (c.next(b, e) && e - b >= 3 && e - b <= 8 && tokenIs(e - 3, e, "off") && std::memcmp(e - 3, "OFF", 3) == 0) {
    bool header = true;
    for (const char* q = b; q != e - 3; ++q) header = header && std::strchr("STCN4n", *q) != nullptr;
    if (header) return Format::Off;
  }
  return Format::Unknown;
}

// Weaker guesses for data without a known extension: OBJ statements, text STL/OFF shapes.
Format weakSniff(const uint8_t* data, size_t size) {
  const size_t probe = size < 65536 ? size : 65536;
  if (hasBinaryByte(data, probe)) return Format::Unknown;
  TextCursor c(data, probe);
  c.commentChar = '#';
  const char* b;
  const char* e;
  int objStatements = 0;
  // OBJ: the first few statements are OBJ keywords and at least one is v or f.
  bool geometry = false;
  for (int i = 0; i < 8 && c.next(b, e); ++i) {
    static const char* const keywords[] = {"v", "vt", "vn", "vp", "f", "g", "o", "s", "usemtl", "mtllib", "l"};
    bool known = false;
    for (const char* k : keywords) known = known || (static_cast<size_t>(e - b) == std::strlen(k) && std::memcmp(b, k, e - b) == 0);
    if (!known) break;
    geometry = geometry || ((e - b) == 1 && (*b == 'v' || *b == 'f'));
    ++objStatements;
    c.skipLine();
  }
  if (geometry && objStatements >= 1) return Format::Obj;
  TextCursor s(data, probe);
  if (s.next(b, e) && tokenIs(b, e, "solid")) return Format::Stl;
  return Format::Unknown;
}

// A tetrahedral mesh (.tet) read as the solid it fills: its boundary surface (faces of one tet,
// outward), vertices used by no boundary face dropped. The geodesic method re-reads the tets.
ReadMeshResult readTetBoundary(const uint8_t* data, size_t size) {
  ReadMeshResult r;
  TetMeshResult tets = readTetMesh(data, size);
  if (!tets.ok()) {
    r.status = tets.status;
    r.message = tets.message;
    return r;
  }
  r.format = "tet";
  r.warnings = tets.warnings;
  const Mesh boundary = tetBoundary(tets.mesh);
  std::vector<uint32_t> remap(boundary.vertexCount(), UINT32_MAX);
  for (uint32_t v : boundary.triangles) {
    if (remap[v] == UINT32_MAX) {
      remap[v] = static_cast<uint32_t>(r.mesh.positions.size() / 3);
      for (int a = 0; a < 3; ++a) r.mesh.positions.push_back(boundary.positions[3 * size_t(v) + a]);
    }
    r.mesh.triangles.push_back(remap[v]);
  }
  return r;
}

ReadMeshResult readAs(Format f, const uint8_t* data, size_t size) {
  switch (f) {
    case Format::Stl: return readStl(data, size);
    case Format::Obj: return readObj(data, size);
    case Format::Off: return readOff(data, size);
    case Format::Ply: return readPly(data, size);
    case Format::ThreeMf: return read3mf(data, size);
    case Format::Tet: return readTetBoundary(data, size);
    case Format::Unknown: break;
  }
  ReadMeshResult r;
  r.status = Status::UnsupportedFormat;
  r.message = "unsupported format";
  return r;
}

ReadMeshResult readChecked(const uint8_t* data, size_t size, const std::string& nameHint) {
  ReadMeshResult r;
  if (data == nullptr || size == 0) {
    r.status = Status::EmptyInput;
    r.message = "no data" + (nameHint.empty() ? std::string() : " in '" + nameHint + "'");
    return r;
  }
  const Format byName = formatFromName(nameHint);
  const Format byContent = strongSniff(data, size);
  std::string note;
  Format chosen = byName;
  if (byName == Format::Unknown) {
    chosen = byContent != Format::Unknown ? byContent : weakSniff(data, size);
  } else {
    // Clear signatures win over the name; so does OBJ text in a file named as another format.
    Format other = byContent;
    if (other == Format::Unknown && byName != Format::Obj && weakSniff(data, size) == Format::Obj) other = Format::Obj;
    if (other != Format::Unknown && other != byName) {
      chosen = other;
      note = "'" + nameHint + "' is named as " + formatName(byName) + " but its content is " + formatName(other) +
             "; read as " + formatName(other);
    }
  }
  if (chosen == Format::Unknown) {
    r.status = Status::UnsupportedFormat;
    r.message = "format not recognised from the name" + (nameHint.empty() ? std::string() : " '" + nameHint + "'") +
                " or the content (supported: STL, OBJ, OFF, PLY, 3MF, TET)";
    return r;
  }
  r = readAs(chosen, data, size);
  if (!note.empty()) r.warnings.insert(r.warnings.begin(), note);
  if (r.ok() && r.mesh.triangles.empty()) {
    r.status = Status::EmptyInput;
    r.message = std::string(formatName(chosen)) + " data has no faces (" + std::to_string(r.mesh.vertexCount()) + " vertices)";
  }
  if (!r.ok()) r.mesh = Mesh();
  return r;
}

}  // namespace

ReadMeshResult readMesh(const uint8_t* data, size_t size, const std::string& nameHint) {
  try {
    return readChecked(data, size, nameHint);
  } catch (const std::bad_alloc&) {
    return failed<ReadMeshResult>(
        allocationFailed("reading " + (nameHint.empty() ? std::string("the mesh") : "'" + nameHint + "'")));
  } catch (...) {
    ReadMeshResult r;
    r.status = Status::Internal;
    r.message = "unexpected exception while reading " + (nameHint.empty() ? std::string("the mesh") : "'" + nameHint + "'");
    return r;
  }
}

ReadMeshResult readMeshFile(const std::string& path) {
  ReadMeshResult r;
  try {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      r.status = Status::IoError;
      r.message = "cannot read '" + path + "': it is a folder";
      return r;
    }
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
      r.status = Status::IoError;
      r.message = "cannot open '" + path + "': " + std::strerror(errno);
      return r;
    }
    std::vector<uint8_t> bytes;
    uint8_t buffer[1 << 16];
    size_t n;
    if (std::fseek(f, 0, SEEK_END) == 0) {
      const long length = std::ftell(f);
      if (length > 0 && static_cast<uint64_t>(length) < (uint64_t{1} << 40)) bytes.reserve(static_cast<size_t>(length));
      std::fseek(f, 0, SEEK_SET);
    }
    while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) bytes.insert(bytes.end(), buffer, buffer + n);
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) {
      r.status = Status::IoError;
      r.message = "cannot read '" + path + "'";
      return r;
    }
    return readMesh(bytes.data(), bytes.size(), path);
  } catch (const std::bad_alloc&) {
    return failed<ReadMeshResult>(allocationFailed("reading '" + path + "'"));
  }
}

}  // namespace omnislice

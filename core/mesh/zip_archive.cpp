// SPDX-License-Identifier: MIT
// ZIP reading from the PKWARE APPNOTE layout: end-of-central-directory record (searched from the
// end, past an optional comment), optional ZIP64 records, central directory, local headers.
#include "mesh/zip_archive.h"

#include <cstdint>

#include "mesh/inflate.h"

namespace omnislice {
namespace {

constexpr uint32_t kLocalSig = 0x04034b50;
constexpr uint32_t kCentralSig = 0x02014b50;
constexpr uint32_t kEndSig = 0x06054b50;
constexpr uint32_t kZip64EndSig = 0x06064b50;
constexpr uint32_t kZip64LocatorSig = 0x07064b50;

inline uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }
inline uint32_t le32(const uint8_t* p) { return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24; }
inline uint64_t le64(const uint8_t* p) { return uint64_t{le32(p)} | uint64_t{le32(p + 4)} << 32; }

ZipDirectory failDir(Status s, std::string message) {
  ZipDirectory d;
  d.status = s;
  d.message = std::move(message);
  return d;
}

}  // namespace

ZipDirectory readZipDirectory(const uint8_t* data, size_t size) {
  const bool startsLikeZip = size >= 4 && le32(data) == kLocalSig;
  // The end record is 22 bytes plus a comment of at most 65535 bytes.
  size_t endPos = SIZE_MAX;
  if (size >= 22) {
    const size_t lowest = size - 22 > 65535 ? size - 22 - 65535 : 0;
    for (size_t i = size - 22 + 1; i-- > lowest;) {
      if (le32(data + i) == kEndSig && i + 22 + le16(data + i + 20) <= size) {
        endPos = i;
        break;
      }
    }
  }
  if (endPos == SIZE_MAX) {
    if (startsLikeZip) return failDir(Status::TruncatedFile, "ZIP: end of central directory missing (file cut off?)");
    return failDir(Status::ParseError, "ZIP: no end of central directory record");
  }
  const uint8_t* end = data + endPos;
  uint64_t entryCount = le16(end + 10);
  uint64_t dirSize = le32(end + 12);
  uint64_t dirOffset = le32(end + 16);
  if (entryCount == 0xFFFF || dirSize == 0xFFFFFFFFull || dirOffset == 0xFFFFFFFFull) {
    // ZIP64: a locator just before the end record points at the ZIP64 end record.
    if (endPos >= 20 && le32(data + endPos - 20) == kZip64LocatorSig) {
      const uint64_t z64 = le64(data + endPos - 20 + 8);
      if (z64 > size || size - z64 < 56 || le32(data + z64) != kZip64EndSig) {
        return failDir(Status::ParseError, "ZIP: bad ZIP64 end of central directory record");
      }
      entryCount = le64(data + z64 + 32);
      dirSize = le64(data + z64 + 40);
      dirOffset = le64(data + z64 + 48);
    }
  }
  if (dirOffset > size || dirSize > size - dirOffset) {
    return failDir(Status::TruncatedFile, "ZIP: central directory lies past the end of the file");
  }
  ZipDirectory dir;
  const uint8_t* p = data + dirOffset;
  const uint8_t* dirEnd = p + dirSize;
  for (uint64_t i = 0; i < entryCount; ++i) {
    if (dirEnd - p < 46 || le32(p) != kCentralSig) return failDir(Status::ParseError, "ZIP: bad central directory entry " + std::to_string(i));
    ZipEntry e;
    e.flags = le16(p + 8);
    e.method = le16(p + 10);
    e.crc = le32(p + 16);
    e.compressedSize = le32(p + 20);
    e.uncompressedSize = le32(p + 24);
    const size_t nameLen = le16(p + 28);
    const size_t extraLen = le16(p + 30);
    const size_t commentLen = le16(p + 32);
    e.localHeaderOffset = le32(p + 42);
    if (static_cast<size_t>(dirEnd - p) < 46 + nameLen + extraLen + commentLen) {
      return failDir(Status::ParseError, "ZIP: central directory entry " + std::to_string(i) + " overruns the directory");
    }
    e.name.assign(reinterpret_cast<const char*>(p + 46), nameLen);
    // ZIP64 extended information: 64-bit values for the fields saturated at 0xFFFFFFFF.
    const uint8_t* x = p + 46 + nameLen;
    const uint8_t* xEnd = x + extraLen;
    while (xEnd - x >= 4) {
      const uint16_t id = le16(x);
      const uint16_t len = le16(x + 2);
      if (xEnd - x - 4 < len) break;
      if (id == 0x0001) {
        const uint8_t* f = x + 4;
        const uint8_t* fEnd = f + len;
        if (e.uncompressedSize == 0xFFFFFFFFull && fEnd - f >= 8) e.uncompressedSize = le64(f), f += 8;
        if (e.compressedSize == 0xFFFFFFFFull && fEnd - f >= 8) e.compressedSize = le64(f), f += 8;
        if (e.localHeaderOffset == 0xFFFFFFFFull && fEnd - f >= 8) e.localHeaderOffset = le64(f), f += 8;
      }
      x += 4 + len;
    }
    dir.entries.push_back(std::move(e));
    p += 46 + nameLen + extraLen + commentLen;
  }
  return dir;
}

ZipExtractResult extractZipEntry(const uint8_t* data, size_t size, const ZipEntry& entry) {
  ZipExtractResult r;
  auto fail = [&r, &entry](Status s, const std::string& what) {
    r.status = s;
    r.message = "ZIP entry '" + entry.name.substr(0, 80) + "': " + what;
    r.data.clear();
    return r;
  };
  if (entry.flags & 1) return fail(Status::UnsupportedFormat, "encrypted entries are not supported");
  if (entry.method != 0 && entry.method != 8) {
    return fail(Status::UnsupportedFormat, "compression method " + std::to_string(entry.method) + " is not supported");
  }
  const uint64_t lh = entry.localHeaderOffset;
  if (lh > size || size - lh < 30) return fail(Status::TruncatedFile, "local header past the end of the file");
  if (le32(data + lh) != kLocalSig) return fail(Status::ParseError, "bad local header signature");
  const uint64_t start = lh + 30 + le16(data + lh + 26) + le16(data + lh + 28);
  if (start > size || entry.compressedSize > size - start) return fail(Status::TruncatedFile, "data past the end of the file");
  const uint8_t* src = data + start;
  if (entry.method == 0) {
    if (entry.compressedSize != entry.uncompressedSize) return fail(Status::ParseError, "stored entry with different sizes");
    r.data.assign(src, src + entry.compressedSize);
  } else {
    // DEFLATE expands at most about 1032:1; a larger declared size is corrupt (or a bomb).
    if (entry.uncompressedSize > 1032 * entry.compressedSize + 1024) return fail(Status::ParseError, "implausible uncompressed size");
    InflateResult inf = inflateRaw(src, static_cast<size_t>(entry.compressedSize), static_cast<size_t>(entry.uncompressedSize));
    if (!inf.ok()) return fail(inf.status, inf.message);
    if (inf.data.size() != entry.uncompressedSize) {
      return fail(Status::ParseError, "inflated to " + std::to_string(inf.data.size()) + " bytes, directory says " +
                                          std::to_string(entry.uncompressedSize));
    }
    r.data = std::move(inf.data);
  }
  if (crc32(r.data.data(), r.data.size()) != entry.crc) return fail(Status::ParseError, "CRC-32 mismatch");
  return r;
}

}  // namespace omnislice

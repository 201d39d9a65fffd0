// SPDX-License-Identifier: MIT
// Minimal read-only ZIP access for 3MF containers: central directory listing (ZIP64 aware) and
// extraction of stored or deflated entries with CRC-32 check.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"

namespace omnislice {

struct ZipEntry {
  std::string name;              // path inside the archive, '/' separated
  uint16_t method = 0;           // 0 stored, 8 deflated
  uint16_t flags = 0;            // general-purpose flags (bit 0: encrypted)
  uint32_t crc = 0;
  uint64_t compressedSize = 0;   // bytes
  uint64_t uncompressedSize = 0; // bytes
  uint64_t localHeaderOffset = 0;
};

struct ZipDirectory : Outcome {
  std::vector<ZipEntry> entries;
};

// Lists the entries of a ZIP archive held in memory. Statuses: TruncatedFile when the data
// starts like a ZIP but its end-of-central-directory record is missing (cut-off file) or the
// directory runs past the end, ParseError for inconsistent records.
ZipDirectory readZipDirectory(const uint8_t* data, size_t size);

struct ZipExtractResult : Outcome {
  std::vector<uint8_t> data;
};

// Extracts one entry listed by readZipDirectory from the same data. Statuses: TruncatedFile
// (entry data past the end), ParseError (bad local header, invalid DEFLATE data, size or CRC
// mismatch), UnsupportedFormat (encrypted entry or a compression method other than 0 or 8).
ZipExtractResult extractZipEntry(const uint8_t* data, size_t size, const ZipEntry& entry);

}  // namespace omnislice

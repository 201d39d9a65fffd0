// SPDX-License-Identifier: MIT
// Raw DEFLATE decompression (RFC 1951: stored, fixed-Huffman and dynamic-Huffman blocks), in
// plain C++ so native and wasm builds decode 3MF containers identically without zlib.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/status.h"

namespace omnislice {

struct InflateResult : Outcome {
  std::vector<uint8_t> data;  // decompressed bytes (empty on failure)
  size_t consumed = 0;        // compressed bytes used, up to the byte holding the final bit
};

// Decompresses one raw DEFLATE stream (no zlib or gzip wrapper) from data[0, size).
// maxOutput bounds the output (bytes; the caller passes the size it expects, which also stops
// decompression bombs). Statuses: TruncatedFile when the stream ends before its final block,
// ParseError for invalid codes, distances or an output larger than maxOutput. Never throws
// except std::bad_alloc.
InflateResult inflateRaw(const uint8_t* data, size_t size, size_t maxOutput);

// CRC-32 (ISO 3309 / zip / gzip polynomial) of data, continuing from a previous value.
uint32_t crc32(const uint8_t* data, size_t size, uint32_t previous = 0);

}  // namespace omnislice

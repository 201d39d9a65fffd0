// SPDX-License-Identifier: MIT
// PNG encoding for the thumbnails printer hosts show (program/thumbnail.h): 8-bit RGBA, each row
// filtered (None, Sub or Up, whichever sums smallest), compressed with DEFLATE (fixed Huffman
// codes, LZ77 over a 32 KiB window) in a zlib stream, in plain C++ so native and wasm builds write
// the same bytes without zlib. Base64 (RFC 4648) for the G-code comment block.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace omnislice {

// A zlib stream (RFC 1950: header 78 01, one fixed-Huffman DEFLATE block, Adler-32) of data.
std::vector<uint8_t> zlibCompress(const uint8_t* data, size_t size);

// A PNG file of a width x height RGBA image (rgba: 4 bytes per pixel, rows top to bottom).
// Precondition: width, height >= 1 and rgba.size() == 4 * width * height.
std::vector<uint8_t> encodePngRgba(const std::vector<uint8_t>& rgba, int width, int height);

// Standard base64 with '=' padding.
std::string base64Encode(const std::vector<uint8_t>& bytes);

}  // namespace omnislice

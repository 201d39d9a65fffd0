// SPDX-License-Identifier: MIT
#include "program/png.h"

#include <algorithm>
#include <cstdlib>

#include "mesh/inflate.h"  // crc32

namespace omnislice {

namespace {

// Bits into bytes, least significant bit first (RFC 1951 section 3.1.1).
class BitWriter {
 public:
  explicit BitWriter(std::vector<uint8_t>& out) : out_(out) {}
  void bits(uint32_t value, int count) {
    acc_ |= uint64_t(value) << used_;
    used_ += count;
    while (used_ >= 8) {
      out_.push_back(uint8_t(acc_ & 0xff));
      acc_ >>= 8;
      used_ -= 8;
    }
  }
  // A Huffman code: its bits go most significant first.
  void code(uint32_t code, int length) {
    uint32_t reversed = 0;
    for (int i = 0; i < length; ++i) reversed |= ((code >> i) & 1u) << (length - 1 - i);
    bits(reversed, length);
  }
  void flush() {
    if (used_ > 0) out_.push_back(uint8_t(acc_ & 0xff));
    acc_ = 0;
    used_ = 0;
  }

 private:
  std::vector<uint8_t>& out_;
  uint64_t acc_ = 0;
  int used_ = 0;
};

// The fixed literal/length code (RFC 1951 section 3.2.6).
void literalCode(BitWriter& w, int symbol) {
  if (symbol < 144) {
    w.code(0x30 + symbol, 8);
  } else if (symbol < 256) {
    w.code(0x190 + (symbol - 144), 9);
  } else if (symbol < 280) {
    w.code(symbol - 256, 7);
  } else {
    w.code(0xc0 + (symbol - 280), 8);
  }
}

constexpr int kLengthBase[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr int kLengthExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr int kDistanceBase[30] = {1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
                                   193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr int kDistanceExtra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

void matchCode(BitWriter& w, int length, int distance) {
  int l = 28;
  while (kLengthBase[l] > length) --l;
  literalCode(w, 257 + l);
  if (kLengthExtra[l] > 0) w.bits(uint32_t(length - kLengthBase[l]), kLengthExtra[l]);
  int d = 29;
  while (kDistanceBase[d] > distance) --d;
  w.code(uint32_t(d), 5);
  if (kDistanceExtra[d] > 0) w.bits(uint32_t(distance - kDistanceBase[d]), kDistanceExtra[d]);
}

uint32_t adler32(const uint8_t* data, size_t size) {
  uint32_t a = 1, b = 0;
  for (size_t i = 0; i < size; ++i) {
    a = (a + data[i]) % 65521u;
    b = (b + a) % 65521u;
  }
  return (b << 16) | a;
}

void put32(std::vector<uint8_t>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(uint8_t((v >> s) & 0xff));
}

void chunk(std::vector<uint8_t>& png, const char* type, const std::vector<uint8_t>& data) {
  put32(png, uint32_t(data.size()));
  const size_t start = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), data.begin(), data.end());
  put32(png, crc32(png.data() + start, png.size() - start));
}

}  // namespace

std::vector<uint8_t> zlibCompress(const uint8_t* data, size_t size) {
  std::vector<uint8_t> out = {0x78, 0x01};
  BitWriter w(out);
  w.bits(1, 1);  // BFINAL: the only block
  w.bits(1, 2);  // BTYPE 01: fixed Huffman codes
  // Greedy LZ77: a hash of the next 3 bytes heads a chain of earlier positions in the window.
  constexpr int kHashBits = 15, kWindow = 32768, kMaxChain = 64, kMinMatch = 3, kMaxMatch = 258;
  std::vector<int32_t> head(size_t(1) << kHashBits, -1), prev(kWindow, -1);
  auto hashAt = [&](size_t i) {
    return ((uint32_t(data[i]) << 10) ^ (uint32_t(data[i + 1]) << 5) ^ data[i + 2]) & ((1u << kHashBits) - 1);
  };
  auto insert = [&](size_t i) {
    if (i + kMinMatch > size) return;
    const uint32_t h = hashAt(i);
    prev[i % kWindow] = head[h];
    head[h] = int32_t(i);
  };
  size_t i = 0;
  while (i < size) {
    int bestLength = 0, bestDistance = 0;
    if (i + kMinMatch <= size) {
      const size_t limit = std::min<size_t>(kMaxMatch, size - i);
      int32_t candidate = head[hashAt(i)];
      for (int chain = 0; candidate >= 0 && chain < kMaxChain; ++chain) {
        const size_t c = size_t(candidate);
        if (i - c > size_t(kWindow - 1)) break;
        size_t n = 0;
        while (n < limit && data[c + n] == data[i + n]) ++n;
        if (int(n) > bestLength) {
          bestLength = int(n);
          bestDistance = int(i - c);
          if (n == limit) break;
        }
        const int32_t next = prev[c % kWindow];
        if (next >= candidate) break;  // the slot was reused by a newer position
        candidate = next;
      }
    }
    if (bestLength >= kMinMatch) {
      matchCode(w, bestLength, bestDistance);
      for (int k = 0; k < bestLength; ++k) insert(i + size_t(k));
      i += size_t(bestLength);
    } else {
      literalCode(w, data[i]);
      insert(i);
      ++i;
    }
  }
  literalCode(w, 256);  // end of block
  w.flush();
  put32(out, adler32(data, size));
  return out;
}

std::vector<uint8_t> encodePngRgba(const std::vector<uint8_t>& rgba, int width, int height) {
  const size_t stride = size_t(width) * 4;
  // Each row with the filter whose bytes, read as signed, sum smallest (PNG spec 12.8).
  std::vector<uint8_t> raw;
  raw.reserve((stride + 1) * size_t(height));
  std::vector<uint8_t> candidate(stride), best(stride);
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = rgba.data() + size_t(y) * stride;
    const uint8_t* up = y > 0 ? row - stride : nullptr;
    long bestSum = -1;
    uint8_t bestType = 0;
    for (uint8_t type = 0; type < 3; ++type) {
      long sum = 0;
      for (size_t k = 0; k < stride; ++k) {
        const uint8_t left = k >= 4 ? row[k - 4] : 0;
        const uint8_t above = up ? up[k] : 0;
        const uint8_t v = type == 0 ? row[k] : type == 1 ? uint8_t(row[k] - left) : uint8_t(row[k] - above);
        candidate[k] = v;
        sum += std::abs(int(int8_t(v)));
      }
      if (bestSum < 0 || sum < bestSum) {
        bestSum = sum;
        bestType = type;
        best.swap(candidate);
      }
    }
    raw.push_back(bestType);
    raw.insert(raw.end(), best.begin(), best.end());
  }
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  std::vector<uint8_t> header;
  put32(header, uint32_t(width));
  put32(header, uint32_t(height));
  header.insert(header.end(), {8, 6, 0, 0, 0});  // 8 bits, RGBA, deflate, filter 0, no interlace
  chunk(png, "IHDR", header);
  chunk(png, "IDAT", zlibCompress(raw.data(), raw.size()));
  chunk(png, "IEND", {});
  return png;
}

std::string base64Encode(const std::vector<uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t a = bytes[i], b = i + 1 < bytes.size() ? bytes[i + 1] : 0, c = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const uint32_t v = (a << 16) | (b << 8) | c;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

}  // namespace omnislice

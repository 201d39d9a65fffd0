// SPDX-License-Identifier: MIT
// Raw DEFLATE decoder written from RFC 1951. Huffman codes are decoded with a 10-bit lookup
// table and a canonical bit-by-bit walk for longer codes. Reading past the input pads with
// zero bits and is detected afterwards, so the hot loop has no end-of-input branches.
#include "mesh/inflate.h"

#include <cstring>
#include <string>

namespace omnislice {
namespace {

constexpr int kMaxBits = 15;
constexpr int kFastBits = 10;

constexpr uint16_t kLengthBase[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                      31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr uint8_t kLengthExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                      2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr uint16_t kDistBase[30] = {1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
                                    193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr uint8_t kDistExtra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
constexpr uint8_t kCodeLengthOrder[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};

class BitReader {
 public:
  BitReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  // Low n bits (n <= 32) of the stream without consuming them.
  uint32_t peek(int n) {
    if (count_ < n) refill();
    return static_cast<uint32_t>(buf_ & ((uint64_t{1} << n) - 1));
  }
  void drop(int n) {
    buf_ >>= n;
    count_ -= n;
    consumedBits_ += static_cast<uint64_t>(n);
  }
  uint32_t bits(int n) {
    if (n == 0) return 0;
    const uint32_t v = peek(n);
    drop(n);
    return v;
  }
  // True once more bits were consumed than the input holds.
  bool overrun() const { return consumedBits_ > 8 * static_cast<uint64_t>(size_); }
  uint64_t consumedBits() const { return consumedBits_; }
  // Skips to the next byte boundary and hands out the byte position, emptying the buffer.
  size_t alignToByte() {
    drop(static_cast<int>((8 - consumedBits_ % 8) % 8));
    buf_ = 0;
    count_ = 0;
    pos_ = static_cast<size_t>(consumedBits_ / 8);
    return pos_;
  }
  // Continues reading at byte position pos (after a stored block was copied directly).
  void resumeAt(size_t pos) {
    consumedBits_ = 8 * static_cast<uint64_t>(pos);
    pos_ = pos;
    buf_ = 0;
    count_ = 0;
  }

 private:
  void refill() {
    while (count_ <= 56) {
      const uint64_t byte = pos_ < size_ ? data_[pos_] : 0;
      ++pos_;
      buf_ |= byte << count_;
      count_ += 8;
    }
  }

  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  uint64_t buf_ = 0;
  int count_ = 0;
  uint64_t consumedBits_ = 0;
};

struct Huffman {
  uint16_t fast[1 << kFastBits];  // symbol | length << 9; 0 = code longer than kFastBits (or unused)
  uint16_t count[kMaxBits + 1];   // codes per length
  uint16_t symbol[288];           // symbols ordered by code
};

// Builds the decoding tables from code lengths. False when the lengths over-subscribe the code
// space; incomplete codes are accepted (an unused code then fails when it is met).
bool buildHuffman(Huffman& h, const uint8_t* lengths, int n) {
  std::memset(h.count, 0, sizeof h.count);
  std::memset(h.fast, 0, sizeof h.fast);
  for (int s = 0; s < n; ++s) h.count[lengths[s]]++;
  h.count[0] = 0;
  int left = 1;
  for (int len = 1; len <= kMaxBits; ++len) {
    left <<= 1;
    left -= h.count[len];
    if (left < 0) return false;
  }
  uint16_t offset[kMaxBits + 2];
  offset[1] = 0;
  for (int len = 1; len <= kMaxBits; ++len) offset[len + 1] = static_cast<uint16_t>(offset[len] + h.count[len]);
  uint16_t nextCode[kMaxBits + 1];
  uint32_t code = 0;
  for (int len = 1; len <= kMaxBits; ++len) {
    code = (code + h.count[len - 1]) << 1;
    nextCode[len] = static_cast<uint16_t>(code);
  }
  for (int s = 0; s < n; ++s) {
    const int len = lengths[s];
    if (len == 0) continue;
    h.symbol[offset[len]++] = static_cast<uint16_t>(s);
    const uint32_t c = nextCode[len]++;
    if (len <= kFastBits) {
      // Codes are sent most significant bit first, the reader gathers least significant first.
      uint32_t rev = 0;
      for (int i = 0; i < len; ++i) rev |= ((c >> i) & 1u) << (len - 1 - i);
      for (uint32_t k = rev; k < (1u << kFastBits); k += (1u << len)) {
        h.fast[k] = static_cast<uint16_t>(s | len << 9);
      }
    }
  }
  return true;
}

// Next symbol, or -1 for a code that is not in the table.
inline int decodeSymbol(BitReader& br, const Huffman& h) {
  const uint32_t look = br.peek(kMaxBits);
  const uint16_t entry = h.fast[look & ((1u << kFastBits) - 1)];
  if (entry != 0) {
    br.drop(entry >> 9);
    return entry & 0x1FF;
  }
  // Canonical decoding: codes of each length are consecutive integers.
  int code = 0, first = 0, index = 0;
  for (int len = 1; len <= kMaxBits; ++len) {
    code |= static_cast<int>((look >> (len - 1)) & 1u);
    const int count = h.count[len];
    if (code - first < count) {
      br.drop(len);
      return h.symbol[index + code - first];
    }
    index += count;
    first += count;
    first <<= 1;
    code <<= 1;
  }
  return -1;
}

class Inflater {
 public:
  Inflater(const uint8_t* data, size_t size, size_t maxOutput, InflateResult& r)
      : br_(data, size), data_(data), size_(size), max_(maxOutput), r_(r) {}

  void run() {
    // With a plausible expected size (zip entries), allocate the output once.
    if (max_ <= 1032 * static_cast<uint64_t>(size_) + 1024) out_.resize(max_);
    bool last = false;
    while (!last) {
      last = br_.bits(1) != 0;
      const uint32_t type = br_.bits(2);
      if (br_.overrun()) {
        truncated();
        return;
      }
      bool ok;
      if (type == 0) {
        ok = storedBlock();
      } else if (type == 1) {
        ok = fixedBlock();
      } else if (type == 2) {
        ok = dynamicBlock();
      } else {
        ok = fail(Status::ParseError, "DEFLATE: invalid block type 3");
      }
      if (!ok) return;
    }
    out_.resize(size_out_);
    r_.data = std::move(out_);
    r_.consumed = static_cast<size_t>((br_.consumedBits() + 7) / 8);
  }

 private:
  bool fail(Status s, const std::string& message) {
    r_.status = s;
    r_.message = message;
    return false;
  }
  bool truncated() { return fail(Status::TruncatedFile, "DEFLATE: compressed data ends before the final block"); }

  // Ensures room for n more output bytes within the limit.
  bool reserve(size_t n) {
    if (n > max_ - size_out_) return fail(Status::ParseError, "DEFLATE: output larger than the declared size");
    if (size_out_ + n > out_.size()) {
      size_t cap = out_.size() < 65536 ? 65536 : out_.size() * 2;
      if (cap < size_out_ + n) cap = size_out_ + n;
      if (cap > max_) cap = max_;
      out_.resize(cap);
    }
    return true;
  }

  bool storedBlock() {
    const size_t pos = br_.alignToByte();
    if (size_ < 4 || pos > size_ - 4) return truncated();
    const uint32_t len = data_[pos] | data_[pos + 1] << 8;
    const uint32_t nlen = data_[pos + 2] | data_[pos + 3] << 8;
    if ((len ^ 0xFFFFu) != nlen) return fail(Status::ParseError, "DEFLATE: stored block length check failed");
    if (len > size_ - pos - 4) return truncated();
    if (!reserve(len)) return false;
    // An empty stored block copies nothing (out_ may still be empty: memcpy of a null pointer is
    // undefined even for no bytes; found by npm run fuzz, fuzz/regressions/inflate).
    if (len > 0) std::memcpy(out_.data() + size_out_, data_ + pos + 4, len);
    size_out_ += len;
    br_.resumeAt(pos + 4 + len);
    return true;
  }

  bool fixedBlock() {
    if (!fixedBuilt_) {
      uint8_t lengths[288 + 30];
      int s = 0;
      for (; s < 144; ++s) lengths[s] = 8;
      for (; s < 256; ++s) lengths[s] = 9;
      for (; s < 280; ++s) lengths[s] = 7;
      for (; s < 288; ++s) lengths[s] = 8;
      for (int d = 0; d < 30; ++d) lengths[288 + d] = 5;
      buildHuffman(fixedLit_, lengths, 288);
      buildHuffman(fixedDist_, lengths + 288, 30);
      fixedBuilt_ = true;
    }
    return codes(fixedLit_, fixedDist_);
  }

  bool dynamicBlock() {
    const int nlen = static_cast<int>(br_.bits(5)) + 257;
    const int ndist = static_cast<int>(br_.bits(5)) + 1;
    const int ncode = static_cast<int>(br_.bits(4)) + 4;
    if (br_.overrun()) return truncated();
    if (nlen > 286 || ndist > 30) return fail(Status::ParseError, "DEFLATE: bad code counts in dynamic block header");
    uint8_t lengths[286 + 30];
    std::memset(lengths, 0, sizeof lengths);
    uint8_t clen[19];
    std::memset(clen, 0, sizeof clen);
    for (int i = 0; i < ncode; ++i) clen[kCodeLengthOrder[i]] = static_cast<uint8_t>(br_.bits(3));
    if (br_.overrun()) return truncated();
    if (!buildHuffman(lenCode_, clen, 19)) return fail(Status::ParseError, "DEFLATE: over-subscribed code-length code");
    int i = 0;
    while (i < nlen + ndist) {
      const int sym = decodeSymbol(br_, lenCode_);
      if (br_.overrun()) return truncated();
      if (sym < 0) return fail(Status::ParseError, "DEFLATE: invalid code-length code");
      if (sym < 16) {
        lengths[i++] = static_cast<uint8_t>(sym);
        continue;
      }
      uint8_t value = 0;
      int repeat;
      if (sym == 16) {
        if (i == 0) return fail(Status::ParseError, "DEFLATE: repeat of a code length with no previous length");
        value = lengths[i - 1];
        repeat = 3 + static_cast<int>(br_.bits(2));
      } else if (sym == 17) {
        repeat = 3 + static_cast<int>(br_.bits(3));
      } else {
        repeat = 11 + static_cast<int>(br_.bits(7));
      }
      if (br_.overrun()) return truncated();
      if (i + repeat > nlen + ndist) return fail(Status::ParseError, "DEFLATE: code lengths overflow the declared counts");
      while (repeat-- > 0) lengths[i++] = value;
    }
    if (lengths[256] == 0) return fail(Status::ParseError, "DEFLATE: dynamic block has no end-of-block code");
    if (!buildHuffman(dynLit_, lengths, nlen)) return fail(Status::ParseError, "DEFLATE: over-subscribed literal/length code");
    if (!buildHuffman(dynDist_, lengths + nlen, ndist)) return fail(Status::ParseError, "DEFLATE: over-subscribed distance code");
    return codes(dynLit_, dynDist_);
  }

  // Decodes literals and length/distance pairs up to the end-of-block symbol.
  bool codes(const Huffman& lit, const Huffman& dist) {
    for (;;) {
      const int sym = decodeSymbol(br_, lit);
      if (br_.overrun()) return truncated();
      if (sym < 0) return fail(Status::ParseError, "DEFLATE: invalid literal/length code");
      if (sym < 256) {
        if (size_out_ == out_.size() && !reserve(1)) return false;
        if (size_out_ >= max_) return fail(Status::ParseError, "DEFLATE: output larger than the declared size");
        out_[size_out_++] = static_cast<uint8_t>(sym);
        continue;
      }
      if (sym == 256) return true;
      const int li = sym - 257;
      if (li >= 29) return fail(Status::ParseError, "DEFLATE: invalid length symbol");
      const size_t len = kLengthBase[li] + br_.bits(kLengthExtra[li]);
      const int dsym = decodeSymbol(br_, dist);
      if (br_.overrun()) return truncated();
      if (dsym < 0 || dsym >= 30) return fail(Status::ParseError, "DEFLATE: invalid distance code");
      const size_t d = kDistBase[dsym] + br_.bits(kDistExtra[dsym]);
      if (br_.overrun()) return truncated();
      if (d > size_out_) return fail(Status::ParseError, "DEFLATE: distance reaches before the start of the output");
      if (!reserve(len)) return false;
      uint8_t* o = out_.data() + size_out_;
      const uint8_t* from = o - d;
      for (size_t k = 0; k < len; ++k) o[k] = from[k];  // overlapping copies repeat the pattern
      size_out_ += len;
    }
  }

  BitReader br_;
  const uint8_t* data_;
  size_t size_;
  size_t max_;
  InflateResult& r_;
  std::vector<uint8_t> out_;
  size_t size_out_ = 0;
  Huffman lenCode_, dynLit_, dynDist_, fixedLit_, fixedDist_;
  bool fixedBuilt_ = false;
};

}  // namespace

InflateResult inflateRaw(const uint8_t* data, size_t size, size_t maxOutput) {
  InflateResult r;
  Inflater inflater(data, size, maxOutput, r);
  inflater.run();
  if (!r.ok()) r.data.clear();
  return r;
}

uint32_t crc32(const uint8_t* data, size_t size, uint32_t previous) {
  // Four tables ("slicing by 4"): t[k][b] is the CRC of byte b followed by k zero bytes, so four
  // input bytes are folded per step instead of one.
  struct Tables {
    uint32_t t[4][256];
  };
  static const Tables tables = [] {
    Tables tb;
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      tb.t[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; ++i) {
      for (int k = 1; k < 4; ++k) tb.t[k][i] = (tb.t[k - 1][i] >> 8) ^ tb.t[0][tb.t[k - 1][i] & 0xFF];
    }
    return tb;
  }();
  const auto& t = tables.t;
  uint32_t c = ~previous;
  size_t i = 0;
  for (; i + 4 <= size; i += 4) {
    c ^= uint32_t{data[i]} | uint32_t{data[i + 1]} << 8 | uint32_t{data[i + 2]} << 16 | uint32_t{data[i + 3]} << 24;
    c = t[3][c & 0xFF] ^ t[2][(c >> 8) & 0xFF] ^ t[1][(c >> 16) & 0xFF] ^ t[0][c >> 24];
  }
  for (; i < size; ++i) c = t[0][(c ^ data[i]) & 0xFF] ^ (c >> 8);
  return ~c;
}

}  // namespace omnislice

// SPDX-License-Identifier: MIT
#include "mesh/parse_number.h"

#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

namespace omnislice {
namespace {

// Powers of ten that are exactly representable as doubles (10^0 .. 10^22).
constexpr double kExactPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                  1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                  1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

inline char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool equalsNoCase(const char* b, const char* e, const char* word) {
  const size_t n = std::strlen(word);
  if (static_cast<size_t>(e - b) != n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (lower(b[i]) != word[i]) return false;
  }
  return true;
}

// strtod on a NUL-terminated copy of a range already checked to be a plain decimal number, so
// strtod cannot wander into hex floats or past the range.
double slowParse(const char* begin, const char* end) {
  const size_t n = static_cast<size_t>(end - begin);
  char small[128];
  if (n < sizeof(small)) {
    std::memcpy(small, begin, n);
    small[n] = '\0';
    return std::strtod(small, nullptr);
  }
  std::string copy(begin, end);
  return std::strtod(copy.c_str(), nullptr);
}

}  // namespace

bool parseDouble(const char* begin, const char* end, double& out) {
  const char* p = begin;
  if (p == end) return false;
  bool negative = false;
  if (*p == '+' || *p == '-') {
    negative = *p == '-';
    ++p;
    if (p == end) return false;
  }
  if (!((*p >= '0' && *p <= '9') || *p == '.')) {
    // Non-finite spellings are read as they are; validation reports them later.
    if (equalsNoCase(p, end, "inf") || equalsNoCase(p, end, "infinity")) {
      out = negative ? -std::numeric_limits<double>::infinity()
                     : std::numeric_limits<double>::infinity();
      return true;
    }
    if (equalsNoCase(p, end, "nan")) {
      out = negative ? -std::numeric_limits<double>::quiet_NaN()
                     : std::numeric_limits<double>::quiet_NaN();
      return true;
    }
    return false;
  }
  uint64_t mantissa = 0;
  int significant = 0;     // significant digits accumulated in mantissa
  bool dropped = false;    // more than 19 significant digits: the fast path cannot be exact
  int exp10 = 0;           // decimal exponent correction from digits after '.' / dropped digits
  int digits = 0;
  for (; p != end && *p >= '0' && *p <= '9'; ++p, ++digits) {
    if (significant < 19) {
      mantissa = mantissa * 10 + static_cast<uint64_t>(*p - '0');
      if (mantissa != 0) ++significant;
    } else {
      dropped = true;
      ++exp10;
    }
  }
  if (p != end && *p == '.') {
    ++p;
    for (; p != end && *p >= '0' && *p <= '9'; ++p, ++digits) {
      if (significant < 19) {
        mantissa = mantissa * 10 + static_cast<uint64_t>(*p - '0');
        if (mantissa != 0) ++significant;
        --exp10;
      } else {
        dropped = true;
      }
    }
  }
  if (digits == 0) return false;
  if (p != end && (*p == 'e' || *p == 'E')) {
    ++p;
    bool expNegative = false;
    if (p != end && (*p == '+' || *p == '-')) {
      expNegative = *p == '-';
      ++p;
    }
    if (p == end || *p < '0' || *p > '9') return false;
    int e = 0;
    for (; p != end && *p >= '0' && *p <= '9'; ++p) {
      if (e < 100000) e = e * 10 + (*p - '0');
    }
    exp10 += expNegative ? -e : e;
  }
  if (p != end) return false;
  double value;
  if (mantissa == 0 && !dropped) {
    value = 0.0;
  } else if (!dropped && mantissa <= (uint64_t{1} << 53) && exp10 >= -22 && exp10 <= 22) {
    // Both operands are exact doubles, so one IEEE operation gives the correctly rounded value.
    const double m = static_cast<double>(mantissa);
    value = exp10 >= 0 ? m * kExactPow10[exp10] : m / kExactPow10[-exp10];
  } else {
    out = slowParse(begin, end);
    return true;
  }
  out = negative ? -value : value;
  return true;
}

bool parseInt64(const char* begin, const char* end, int64_t& out) {
  const char* p = begin;
  if (p == end) return false;
  bool negative = false;
  if (*p == '+' || *p == '-') {
    negative = *p == '-';
    ++p;
    if (p == end) return false;
  }
  uint64_t v = 0;
  const uint64_t limit = negative ? uint64_t{1} << 63 : (uint64_t{1} << 63) - 1;
  for (; p != end; ++p) {
    if (*p < '0' || *p > '9') return false;
    const uint64_t d = static_cast<uint64_t>(*p - '0');
    if (v > (limit - d) / 10) return false;
    v = v * 10 + d;
  }
  out = negative ? static_cast<int64_t>(0 - v) : static_cast<int64_t>(v);
  return true;
}

}  // namespace omnislice

// SPDX-License-Identifier: MIT
// Locale-independent number parsing over [begin, end) character ranges (no NUL terminator
// needed), shared by the text mesh readers. Behaves the same natively and in wasm.
#pragma once
#include <cstdint>

namespace omnislice {

// Parses the whole range [begin, end) as one decimal floating-point number: optional sign,
// digits with an optional '.', optional exponent ("-1.5e3", ".5", "7.", "1E-4"), or "inf",
// "infinity", "nan" (any case, optional sign). Returns false when the range is not exactly one
// such number (empty, trailing junk, hex). The result is correctly rounded: an exact fast path
// for up to 19 significant digits and |exponent| <= 22, std::strtod in the "C" format otherwise.
bool parseDouble(const char* begin, const char* end, double& out);

// Parses the whole range [begin, end) as a base-10 integer with optional sign. Returns false on
// an empty range, any other character, or a value outside int64.
bool parseInt64(const char* begin, const char* end, int64_t& out);

}  // namespace omnislice

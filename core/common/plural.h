// SPDX-License-Identifier: MIT
// "1 hole", "3 holes": a count with its noun, for the human messages of reports and errors.
#pragma once
#include <cstddef>
#include <string>

namespace omnislice {

inline std::string plural(size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace omnislice

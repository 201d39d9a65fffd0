// SPDX-License-Identifier: MIT
// Whitespace-separated token scanning over a byte range, shared by the text mesh readers
// (ASCII STL, OFF, ASCII PLY). Header-only and internal. Line numbers for messages are counted
// on demand (lineNumber()), keeping the per-byte loop to a table lookup.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace omnislice {

// Whitespace of the text formats: space, \t, \n, \v, \f, \r.
inline bool isTextSpace(char c) {
  const unsigned u = static_cast<unsigned char>(c);
  return u == ' ' || (u >= '\t' && u <= '\r');
}

struct TextCursor {
  const char* begin = nullptr;
  const char* p = nullptr;
  const char* end = nullptr;
  char commentChar = '\0';  // when set, skips from this character to the end of the line

  TextCursor(const uint8_t* data, size_t size)
      : begin(reinterpret_cast<const char*>(data)), p(begin), end(begin + size) {}

  static bool isSpace(char c) { return isTextSpace(c); }

  // Skips whitespace (and comments).
  void skipSpace() {
    for (;;) {
      while (p != end && isTextSpace(*p)) ++p;
      if (p == end || commentChar == '\0' || *p != commentChar) return;
      while (p != end && *p != '\n') ++p;
    }
  }

  // Next token [b, e) after whitespace; false at the end of the data.
  bool next(const char*& b, const char*& e) {
    skipSpace();
    if (p == end) return false;
    b = p;
    if (commentChar == '\0') {
      while (p != end && !isTextSpace(*p)) ++p;
    } else {
      while (p != end && !isTextSpace(*p) && *p != commentChar) ++p;
    }
    e = p;
    return true;
  }

  // Skips the rest of the current line including its newline.
  void skipLine() {
    while (p != end && *p != '\n') ++p;
    if (p != end) ++p;
  }

  bool atEnd() {
    skipSpace();
    return p == end;
  }

  // 1-based line number of the current position (counts newlines: use for messages only).
  size_t lineNumber() const {
    size_t line = 1;
    for (const char* q = begin; q < p; ++q) line += *q == '\n';
    return line;
  }
};

// Case-insensitive comparison of a token with a lowercase ASCII word.
inline bool tokenIs(const char* b, const char* e, const char* word) {
  for (; b != e; ++b, ++word) {
    if (*word == '\0') return false;
    char c = *b;
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c != *word) return false;
  }
  return *word == '\0';
}

// A token for messages: printable ASCII only, at most 40 characters.
inline std::string tokenForMessage(const char* b, const char* e) {
  std::string s;
  for (; b != e && s.size() < 40; ++b) {
    const unsigned char c = static_cast<unsigned char>(*b);
    s += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  }
  if (b != e) s += "...";
  return "'" + s + "'";
}

}  // namespace omnislice

// SPDX-License-Identifier: MIT
// Whitespace-separated token scanning over a byte range, counting lines for error messages.
// Shared by the text mesh readers (ASCII STL, OFF, ASCII PLY, OBJ); header-only and internal.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace omnislice {

struct TextCursor {
  const char* p = nullptr;
  const char* end = nullptr;
  size_t line = 1;                  // 1-based line of p
  char commentChar = '\0';          // when set, skips from this character to the end of the line

  TextCursor(const uint8_t* data, size_t size)
      : p(reinterpret_cast<const char*>(data)), end(reinterpret_cast<const char*>(data) + size) {}

  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

  // Skips whitespace (and comments), counting newlines.
  void skipSpace() {
    while (p != end) {
      const char c = *p;
      if (c == '\n') {
        ++line;
        ++p;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f') {
        ++p;
      } else if (commentChar != '\0' && c == commentChar) {
        while (p != end && *p != '\n') ++p;
      } else {
        break;
      }
    }
  }

  // Next token [b, e) after whitespace; false at the end of the data.
  bool next(const char*& b, const char*& e) {
    skipSpace();
    if (p == end) return false;
    b = p;
    while (p != end && !isSpace(*p) && !(commentChar != '\0' && *p == commentChar)) ++p;
    e = p;
    return true;
  }

  // Skips the rest of the current line including its newline.
  void skipLine() {
    while (p != end && *p != '\n') ++p;
    if (p != end) {
      ++p;
      ++line;
    }
  }

  bool atEnd() {
    skipSpace();
    return p == end;
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

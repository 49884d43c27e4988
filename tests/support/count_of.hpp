// Test support: how often a phrase occurs in a text (a problem must be told once, a row
// listed once).
#pragma once

#include <cstddef>
#include <string>

namespace ccdlane::test {

inline int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace ccdlane::test

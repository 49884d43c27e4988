// Picks CSV parsing with std::from_chars: locale-independent, whole-field, no exceptions
// from the number conversion itself.
#include "core/solver/picks_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace ccdlane {
namespace {

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

// A field as it may be shown in an error: quoted, at most 40 bytes, anything that is
// not printable ASCII escaped, so that a binary file cannot flood or garble a terminal.
std::string excerpt(std::string_view field) {
  constexpr std::size_t kShown = 40;
  std::string out = "\"";
  for (const char c : field.substr(0, kShown)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7F && c != '"' && c != '\\') {
      out += c;
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  out += '"';
  if (field.size() > kShown) out += "... (" + std::to_string(field.size()) + " bytes)";
  return out;
}

class RowError {
 public:
  RowError(const std::string& source, int line) : prefix_(source + ":" + std::to_string(line) + ": ") {}
  [[noreturn]] void fail(const std::string& what) const { throw PicksCsvError(prefix_ + what); }

 private:
  std::string prefix_;
};

template <class T>
bool parse_whole(std::string_view field, T& out) {
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, out);
  return ec == std::errc() && ptr == end;
}

}  // namespace

PicksCsv parse_picks_csv(std::string_view text, const std::string& source_name) {
  PicksCsv out;
  bool have_header = false;
  int line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view raw = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
    ++line_no;
    const std::string_view row = trim(raw);
    if (row.empty() || row.front() == '#') continue;

    const RowError error(source_name, line_no);
    std::array<std::string_view, 3> fields;
    std::size_t count = 0, start = 0;
    for (;;) {
      const std::size_t comma = row.find(',', start);
      if (count < fields.size()) fields[count] = trim(row.substr(start, comma - start));
      ++count;
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (!have_header) {
      if (count != 3 || fields[0] != "line" || fields[1] != "px" || fields[2] != "py")
        error.fail("expected the header line,px,py, got " + excerpt(row));
      have_header = true;
      continue;
    }
    if (count != 3) error.fail("expected 3 fields (line,px,py), got " + std::to_string(count));
    Pick pick;
    if (!parse_whole(fields[0], pick.line) || pick.line < 0)
      error.fail("line: not a lane-line id (an integer >= 0): " + excerpt(fields[0]));
    if (!parse_whole(fields[1], pick.px) || !std::isfinite(pick.px))
      error.fail("px: not a finite number: " + excerpt(fields[1]));
    if (!parse_whole(fields[2], pick.py) || !std::isfinite(pick.py))
      error.fail("py: not a finite number: " + excerpt(fields[2]));
    out.picks.push_back(pick);
    out.source_lines.push_back(line_no);
  }
  if (!have_header) throw PicksCsvError(source_name + ": no header line,px,py (empty file?)");
  if (out.picks.empty()) throw PicksCsvError(source_name + ": no picks after the header");
  return out;
}

}  // namespace ccdlane

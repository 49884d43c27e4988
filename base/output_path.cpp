// Compared by resolved path components, not by string prefix: "rec2" is not inside "rec".
#include "base/output_path.hpp"

#include <algorithm>
#include <filesystem>

namespace ccdlane {
namespace {

std::filesystem::path resolved(const std::string& p) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) r = fs::absolute(p, ec).lexically_normal();
  if (r.has_relative_path() && r.filename().empty()) r = r.parent_path();  // "dir/" is "dir"
  return r;
}

}  // namespace

bool lies_within(const std::string& output, const std::string& input) {
  std::error_code ec;
  if (std::filesystem::equivalent(output, input, ec)) return true;
  const std::filesystem::path o = resolved(output), i = resolved(input);
  const auto [in_end, out_at] = std::mismatch(i.begin(), i.end(), o.begin(), o.end());
  return in_end == i.end();
}

}  // namespace ccdlane

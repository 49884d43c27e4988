// The shipped /etc/ccdlane/ccdlane.toml (daemon/ccdlane.toml): it documents every key the
// loader knows, each commented-out setting is one the loader accepts, and the defaults it
// shows are the loader's own.
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"

namespace ccdlane {
namespace {

const std::string kShipped = CCDLANE_SOURCE_DIR "/daemon/ccdlane.toml";

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The file's convention: "#key = value" (no space after '#') is a commented-out setting,
// "#[[table]]" a commented-out table header; "# ..." is prose. A setting whose trailing
// comment says "# example" has no default and only shows the form of a value.
struct Uncommented {
  std::string defaults;           // the settings that show defaults uncommented
  std::string everything;         // every setting and example uncommented
  std::vector<std::string> keys;  // "table.key" of every setting, in file order
};

std::string table_name(const std::string& header) {  // "[camera]" / "[[lines]]" -> name
  const auto begin = header.find_first_not_of('[');
  const auto end = header.find(']');
  return header.substr(begin, end - begin);
}

Uncommented uncomment(const std::string& text) {
  Uncommented u;
  std::istringstream in(text);
  std::string line, table;
  while (std::getline(in, line)) {
    const bool setting =
        line.size() > 1 && line[0] == '#' && (std::isalpha(static_cast<unsigned char>(line[1])) || line[1] == '[');
    const std::string body = setting ? line.substr(1) : line;
    if (!body.empty() && body[0] == '[')
      table = table_name(body);
    else if (setting)
      u.keys.push_back(table + "." + body.substr(0, body.find_first_of(" =")));
    const bool example = setting && body.find("# example") != std::string::npos;
    u.everything += body + '\n';
    u.defaults += (example ? line : body) + '\n';
  }
  return u;
}

class ShippedConfig : public ::testing::Test {
 protected:
  void SetUp() override {
    text_ = read_file(kShipped);
    ASSERT_FALSE(text_.empty()) << kShipped << ": missing or empty";
    u_ = uncomment(text_);
  }
  std::string text_;
  Uncommented u_;
};

TEST_F(ShippedConfig, AsShippedItIsTheBuiltInDefault) {
  Config c = parse_config(text_, kShipped);
  c.path.clear();
  EXPECT_EQ(c, default_config());
}

TEST_F(ShippedConfig, TheDefaultsItShowsAreTheLoadersDefaults) {
  Config shown = parse_config(u_.defaults, kShipped + " (defaults uncommented)");
  shown.path.clear();
  EXPECT_EQ(shown, default_config()) << u_.defaults;
}

TEST_F(ShippedConfig, EverySettingAndExampleIsAcceptedByTheLoader) {
  // The loader rejects unknown keys and impossible values, naming the line.
  Config all;
  EXPECT_NO_THROW(all = parse_config(u_.everything, kShipped + " (all uncommented)"));
  // The examples are set, not defaults: otherwise "# example" marks a default.
  EXPECT_FALSE(all == default_config());
  EXPECT_FALSE(all.gyro.device.empty());
  EXPECT_EQ(all.lines.size(), 1u);
}

TEST_F(ShippedConfig, DocumentsEveryKeyTheLoaderKnows) {
  const std::set<std::string> documented(u_.keys.begin(), u_.keys.end());
  EXPECT_EQ(documented.size(), u_.keys.size()) << "a key is documented twice";
  for (const std::string& key : config_keys())
    EXPECT_TRUE(documented.count(key)) << key << " is not documented in " << kShipped;
}

TEST(ShippedConfigConvention, UncommentsSettingsNotProse) {
  const Uncommented u = uncomment(
      "# prose = not a setting\n[camera]\n#Nu = 640  # pixels\n#[[lines]]  # example\n"
      "#y0_mm = 1.0  # example\n");
  EXPECT_EQ(u.keys, (std::vector<std::string>{"camera.Nu", "lines.y0_mm"}));
  EXPECT_EQ(u.defaults,
            "# prose = not a setting\n[camera]\nNu = 640  # pixels\n#[[lines]]  # example\n"
            "#y0_mm = 1.0  # example\n");
  EXPECT_EQ(u.everything,
            "# prose = not a setting\n[camera]\nNu = 640  # pixels\n[[lines]]  # example\n"
            "y0_mm = 1.0  # example\n");
}

}  // namespace
}  // namespace ccdlane

// The picks CSV of docs/interfaces.md: what is accepted, and one exact message per problem.
#include "core/solver/picks_csv.hpp"

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(PicksCsv, ReadsPicksSkippingCommentsAndBlankLines) {
  const PicksCsv csv = parse_picks_csv(
      "# picture (a)\n\nline,px,py\n0,191,501\n  1 , 571.25 ,509.5\r\n# a comment\n\n2,1e2,-3\n", "a.csv");
  ASSERT_EQ(csv.picks.size(), 3u);
  EXPECT_EQ(csv.picks[1].line, 1);
  EXPECT_DOUBLE_EQ(csv.picks[1].px, 571.25);
  EXPECT_DOUBLE_EQ(csv.picks[1].py, 509.5);
  EXPECT_DOUBLE_EQ(csv.picks[2].px, 100.0);
  EXPECT_EQ(csv.source_lines, (std::vector<int>{4, 5, 8}));
}

std::string error_of(const std::string& text) {
  try {
    parse_picks_csv(text, "p.csv");
  } catch (const PicksCsvError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PicksCsv, ProblemsNameFileLineAndField) {
  EXPECT_EQ(error_of("line,px,py\n0,1,2\n0,abc,2\n"), "p.csv:3: px: not a finite number: \"abc\"");
  EXPECT_EQ(error_of("line,px,py\n0,1,nan\n"), "p.csv:2: py: not a finite number: \"nan\"");
  EXPECT_EQ(error_of("line,px,py\n0,1,2x\n"), "p.csv:2: py: not a finite number: \"2x\"");
  EXPECT_EQ(error_of("line,px,py\n1.5,1,2\n"), "p.csv:2: line: not a lane-line id (an integer >= 0): \"1.5\"");
  EXPECT_EQ(error_of("line,px,py\n-1,1,2\n"), "p.csv:2: line: not a lane-line id (an integer >= 0): \"-1\"");
  EXPECT_EQ(error_of("line,px,py\n0,1\n"), "p.csv:2: expected 3 fields (line,px,py), got 2");
  EXPECT_EQ(error_of("line,px,py\n0,1,2,3\n"), "p.csv:2: expected 3 fields (line,px,py), got 4");
  EXPECT_EQ(error_of("# x\nline,py,px\n"), "p.csv:2: expected the header line,px,py, got \"line,py,px\"");
  EXPECT_EQ(error_of("line,px,py\n# nothing\n"), "p.csv: no picks after the header");
  EXPECT_EQ(error_of(""), "p.csv: no header line,px,py (empty file?)");
}

}  // namespace
}  // namespace ccdlane

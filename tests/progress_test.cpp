// Progress on stderr: what the display writes for a stage, on a terminal and into a log (the
// command line's use of it: design_cli_test; the search's reports: objective_test).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gridshell/core/progress_display.h"

using gridshell::ProgressDisplay;

namespace {

/// Everything written to `f` so far.
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;) s += static_cast<char>(c);
  return s;
}

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t at = 0; (at = s.find(what, at)) != std::string::npos; at += what.size()) ++n;
  return n;
}

}  // namespace

TEST(Progress, LogLinesAtEachQuarterNotAtEveryCall) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    ProgressDisplay d(f, /*terminal=*/false, /*show_after=*/0);
    for (int k = 0; k <= 100; ++k) d.report("cvt", k / 100.0, std::to_string(k) + "/100");
  }
  const std::string s = contents(f);
  std::fclose(f);
  // 0 %, 25 %, 50 %, 75 % and 100 %: five lines for a hundred calls, each naming the stage.
  EXPECT_EQ(count(s, "\n"), 5) << s;
  EXPECT_EQ(count(s, "[cvt]"), 5) << s;
  EXPECT_NE(s.find(" 25% 25/100"), std::string::npos) << s;
  EXPECT_NE(s.find("100% 100/100"), std::string::npos) << s;
  EXPECT_EQ(s.find('\r'), std::string::npos);  // no carriage returns in a log
}

TEST(Progress, AStageShorterThanTheThresholdIsNotShown) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    ProgressDisplay d(f, false, /*show_after=*/3600);
    for (int k = 0; k <= 10; ++k) d.report("quick", k / 10.0, "");
  }
  EXPECT_EQ(contents(f), "");
  std::fclose(f);
}

TEST(Progress, TerminalBarIsRedrawnInPlaceAndLogLinesGoAboveIt) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    ProgressDisplay d(f, /*terminal=*/true, 0);
    d.report("path", 0.5, "step 3");
    d.log("a log line\n");
    d.report("path", 1.0, "done");
  }
  const std::string s = contents(f);
  std::fclose(f);
  // The bar, cleared before the log line, drawn again after it; the finished bar ends its line.
  const std::size_t bar = s.find("[path]"), clear = s.find("\r\033[K"), log = s.find("a log line\n");
  ASSERT_NE(bar, std::string::npos) << s;
  ASSERT_NE(log, std::string::npos) << s;
  EXPECT_LT(bar, clear);
  EXPECT_LT(clear, log);
  EXPECT_NE(s.find("[path]", log), std::string::npos) << s;  // redrawn below the log line
  EXPECT_NE(s.find(" 50% step 3"), std::string::npos) << s;
  EXPECT_NE(s.find("100% done"), std::string::npos) << s;
  EXPECT_EQ(s.back(), '\n');
}

TEST(Progress, NonFiniteAndOutOfRangeFractionsAreClamped) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    ProgressDisplay d(f, false, 0);
    d.report("odd", std::nan(""), "");
    d.report("odd", 7.0, "");
  }
  const std::string s = contents(f);
  std::fclose(f);
  EXPECT_EQ(s.find("nan"), std::string::npos) << s;
  EXPECT_NE(s.find("  0%"), std::string::npos) << s;
  EXPECT_NE(s.find("100%"), std::string::npos) << s;
}

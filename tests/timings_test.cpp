// core/timings.h: stage seconds in run order, repeated stages summed, report.json's object form;
// core/enum_words.h: one table per mode enum for its words.

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

#include "gridshell/core/enum_words.h"
#include "gridshell/core/error.h"
#include "gridshell/core/timings.h"

using namespace gridshell;

TEST(Timings, KeepsRunOrderAndSumsARepeatedStage) {
  Timings t;
  t.add("field", 0.5);
  t.add("tessellation", 1.25);
  t.add("field", 0.25);  // a retry: same stage again
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.begin()->first, "field");
  EXPECT_DOUBLE_EQ(t.get("field"), 0.75);
  EXPECT_DOUBLE_EQ(t.get("tessellation"), 1.25);
  EXPECT_DOUBLE_EQ(t.get("analysis"), 0.0);
  EXPECT_FALSE(t.contains("analysis"));
  EXPECT_DOUBLE_EQ(t.sum(), 2.0);
  t["analysis"] = 3.0;
  EXPECT_DOUBLE_EQ(t.sum(), 5.0);
  EXPECT_EQ((t.end() - 1)->first, "analysis");
}

TEST(Timings, WritesAnObjectOfStageSeconds) {
  const Timings t{{"load", 0.125}, {"write", 2.0}, {"load", 0.375}};
  const nlohmann::json j = t;
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.size(), 2u);
  EXPECT_DOUBLE_EQ(j.at("load").get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j.at("write").get<double>(), 2.0);
  EXPECT_TRUE(nlohmann::json(Timings{}).is_object());
}

// sleep_for waits at least its duration on the steady clock (never less, however loaded the
// machine), so each lap has a lower bound a stopwatch that returned 0 (or a lap that did not
// restart) would miss; no upper bound is asserted.
TEST(Timings, StopwatchLapsAddUpToItsTotal) {
  Stopwatch total, lap;
  double laps = 0;
  for (int i = 1; i <= 3; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2 * i));
    const double s = lap.lap();
    EXPECT_GE(s, 0.002 * i) << "lap " << i;
    laps += s;
  }
  EXPECT_GE(laps, 0.012);
  EXPECT_LE(laps, total.seconds());
  // A lap restarts: right after one, the next is shorter than the whole.
  EXPECT_LT(lap.seconds(), total.seconds());
}

namespace {
enum class Mode { fast, exact };
constexpr EnumWords<Mode, 2> kModeWords{{{"fast", Mode::fast}, {"exact", Mode::exact}}};
}  // namespace

TEST(EnumWords, ParseAndNameReadTheSameTable) {
  EXPECT_STREQ(word_of(Mode::exact, kModeWords), "exact");
  EXPECT_EQ(parse_word("fast", "--mode", kModeWords), Mode::fast);
  EXPECT_FALSE(find_word("slow", kModeWords).has_value());
  try {
    parse_word("slow", "--mode", kModeWords);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'slow' is not one of fast, exact"), std::string::npos)
        << e.what();
  }
}

// A state flapping faster than the settle time is said once when it settles, with how long it
// flapped; ordinary changes are said at once; nothing that settles goes unsaid.
#include <gtest/gtest.h>

#include "uav/shared/state_news.hpp"

namespace uav {
namespace {

TEST(StateNews, ChangesFarApartAreSaidAtOnce) {
  StateNews news(2.0);
  EXPECT_EQ(news.Update("", 0.0), std::nullopt);  // nothing to report
  EXPECT_EQ(news.Update("avoiding", 1.0), "avoiding");
  EXPECT_EQ(news.Update("avoiding", 2.0), std::nullopt);
  EXPECT_EQ(news.Update("way clear", 5.0), "way clear");
  EXPECT_EQ(news.said(), "way clear");
}

TEST(StateNews, FlappingEveryThirdOfASecondIsSaidOnceWithHowLongItLasted) {
  StateNews news(2.0);
  EXPECT_EQ(news.Update("way clear", 0.0), "way clear");
  int said = 0;
  const char* cycle[] = {"avoiding", "no data", "way clear"};
  double t = 10.0;
  std::optional<std::string> s = news.Update("avoiding", t);
  EXPECT_EQ(s, "avoiding");  // the first change is news
  for (int k = 1; k <= 30; ++k) {  // 9 s of flapping at 0.3 s
    t += 0.3;
    if (news.Update(cycle[k % 3], t)) ++said;
  }
  EXPECT_EQ(said, 0);
  // It settles on "avoiding": said once, with the flapping's length and states.
  const double settled_at = t + 0.3;
  EXPECT_EQ(news.Update("avoiding", settled_at), std::nullopt);
  EXPECT_EQ(news.Update("avoiding", settled_at + 1.0), std::nullopt);
  const auto summary = news.Update("avoiding", settled_at + 2.0);
  ASSERT_TRUE(summary);
  EXPECT_EQ(*summary, "avoiding again (after 9.0 s of changes between avoiding, no data and way clear)");
  EXPECT_EQ(news.Update("avoiding", settled_at + 3.0), std::nullopt);
  // Calm again: the next change is said at once.
  EXPECT_EQ(news.Update("way clear", settled_at + 10.0), "way clear");
}

TEST(StateNews, AFlapThatSettlesOnANewStateSaysThatState) {
  StateNews news(1.0);
  EXPECT_EQ(news.Update("a", 0.0), "a");
  EXPECT_EQ(news.Update("b", 0.5), std::nullopt);
  EXPECT_EQ(news.Update("c", 0.8), std::nullopt);
  EXPECT_EQ(news.Update("c", 1.9), "c (after 0.8 s of changes between a, b and c)");
}

}  // namespace
}  // namespace uav

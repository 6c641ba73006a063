#include <gtest/gtest.h>

#include "uav/shared/command_grammar.hpp"

namespace uav {
namespace {

TEST(CommandGrammar, ParsesEveryCommand) {
  EXPECT_EQ(ParseCommand("arm").command->id, CommandId::kArm);
  EXPECT_EQ(ParseCommand("disarm").command->id, CommandId::kDisarm);
  EXPECT_EQ(ParseCommand("hover").command->id, CommandId::kHover);
  EXPECT_EQ(ParseCommand("land").command->id, CommandId::kLand);
  auto t = ParseCommand("  takeoff   10 ");
  ASSERT_TRUE(t.ok()) << t.error;
  EXPECT_EQ(t.command->args, std::vector<double>{10.0});
  auto g = ParseCommand("goto 20 10 15");
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g.command->args, (std::vector<double>{20, 10, 15}));
  EXPECT_EQ(ParseCommand("HOVER").command->id, CommandId::kHover);
}

TEST(CommandGrammar, TextRoundTrips) {
  for (const char* s : {"arm", "takeoff 12.5", "goto -3 4.25 30", "land"}) {
    const auto c = ParseCommand(s);
    ASSERT_TRUE(c.ok());
    const auto again = ParseCommand(c.command->Text());
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again.command->id, c.command->id);
    EXPECT_EQ(again.command->args, c.command->args);
  }
}

// `param NAME VALUE`: the name is a vehicle parameter, the value held to that parameter's limits.
TEST(CommandGrammar, ParamNamesAVehicleParameterAndHoldsTheValueToItsLimits) {
  const auto p = ParseCommand("param ctl_speed_max_xy 4.5");
  ASSERT_TRUE(p.ok()) << p.error;
  EXPECT_EQ(p.command->id, CommandId::kParam);
  EXPECT_EQ(p.command->parameter, "ctl_speed_max_xy");
  EXPECT_EQ(p.command->args, std::vector<double>{4.5});
  EXPECT_EQ(p.command->Text(), "param ctl_speed_max_xy 4.5");
  EXPECT_EQ(ParseCommand(p.command->Text()).command->parameter, "ctl_speed_max_xy");
  EXPECT_NE(ParseCommand("param ctl_speed_max 4").error.find("unknown parameter 'ctl_speed_max'"), std::string::npos);
  EXPECT_NE(ParseCommand("param ctl_speed_max_xy 400").error.find("ctl_speed_max_xy = 400 is outside ["), std::string::npos);
  EXPECT_NE(ParseCommand("param ctl_speed_max_xy nan").error.find("not a finite number"), std::string::npos);
  EXPECT_NE(ParseCommand("param ctl_speed_max_xy").error.find("missing argument value"), std::string::npos);
  EXPECT_NE(ParseCommand("param").error.find("missing argument name"), std::string::npos);
  EXPECT_NE(ArgumentHint("param ctl_speed_max_xy").find("m/s"), std::string::npos);
}

struct BadCase {
  const char* text;
  const char* error_contains;
};
class CommandGrammarRejects : public ::testing::TestWithParam<BadCase> {};

TEST_P(CommandGrammarRejects, WithAMessageNamingTheProblem) {
  const auto r = ParseCommand(GetParam().text);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find(GetParam().error_contains), std::string::npos)
      << "error was: " << r.error;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CommandGrammarRejects,
    ::testing::Values(BadCase{"", "empty"}, BadCase{"   ", "empty"},
                      BadCase{"fly", "unknown command 'fly'"},
                      BadCase{"takeoff", "missing argument alt_m"},
                      BadCase{"takeoff 10 20", "unexpected extra argument '20'"},
                      BadCase{"hover now", "unexpected extra argument 'now'"},
                      BadCase{"goto 1 2", "missing argument alt_m"},
                      BadCase{"takeoff ten", "not a number: 'ten'"},
                      BadCase{"takeoff 10m", "not a number: '10m'"},
                      BadCase{"takeoff nan", "not a finite number"},
                      BadCase{"takeoff NaN", "not a finite number"},
                      BadCase{"takeoff inf", "not a finite number"},
                      BadCase{"goto 1 -inf 5", "east_m is not a finite number"},
                      BadCase{"takeoff 0.999", "alt_m = 0.999 is outside [1, 120]"},
                      BadCase{"takeoff 120.001", "outside [1, 120]"},
                      BadCase{"takeoff -5", "outside"},
                      BadCase{"goto 1000.5 0 10", "north_m = 1000.5 is outside [-1000, 1000]"},
                      BadCase{"goto 0 -1000.5 10", "east_m"},
                      BadCase{"goto 0 0 0.5", "alt_m"},
                      BadCase{"goto 0 0 121", "alt_m"},
                      BadCase{"chirp 0 0.05 0.2 3 30", "channel = 0 is outside [1, 4]"},
                      BadCase{"chirp 5 0.05 0.2 3 30", "channel = 5 is outside [1, 4]"},
                      BadCase{"chirp 1.5 0.05 0.2 3 30", "channel must be a whole number"},
                      BadCase{"chirp 1 0.009 0.2 3 30", "amplitude = 0.009 is outside [0.01, 0.3]"},
                      BadCase{"chirp 1 0.301 0.2 3 30", "amplitude = 0.301 is outside [0.01, 0.3]"},
                      BadCase{"chirp 1 0.05 0.04 3 30", "f0_hz = 0.04 is outside [0.05, 5]"},
                      BadCase{"chirp 1 0.05 0.2 10.5 30", "f1_hz = 10.5 is outside [0.1, 10]"},
                      BadCase{"chirp 1 0.05 0.2 3 4.9", "duration_s = 4.9 is outside [5, 120]"},
                      BadCase{"chirp 1 0.05 0.2 3 nan", "duration_s is not a finite number"},
                      BadCase{"chirp 1 0.05 0.2 3", "missing argument duration_s"},
                      BadCase{"arm\x01", "control character"}));

TEST(CommandGrammar, AcceptsBothSidesOfEveryLimitInclusive) {
  EXPECT_TRUE(ParseCommand("takeoff 1").ok());
  EXPECT_TRUE(ParseCommand("takeoff 120").ok());
  EXPECT_TRUE(ParseCommand("goto -1000 1000 1").ok());
  EXPECT_TRUE(ParseCommand("goto 1000 -1000 120").ok());
  EXPECT_TRUE(ParseCommand("goto 1e2 -2.5e1 1.5e1").ok());
  EXPECT_TRUE(ParseCommand("chirp 1 0.01 0.05 0.1 5").ok());
  EXPECT_TRUE(ParseCommand("chirp 4 0.3 5 10 120").ok());
}

TEST(CommandGrammar, RejectsOverlongLine) {
  EXPECT_TRUE(ParseCommand(std::string(kMaxCommandLength - 5, ' ') + "arm").ok());
  const auto r = ParseCommand("arm" + std::string(kMaxCommandLength, ' '));
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("limit is 256"), std::string::npos);
}

// `transition fw|mc`: an argument given as one of its words, or the number it stands for; the
// canonical text uses the word.
TEST(CommandGrammar, KeywordArgumentsTakeTheirWordsOrNumbers) {
  const ParseResult fw = ParseCommand("transition FW");
  ASSERT_TRUE(fw.ok()) << fw.error;
  EXPECT_EQ(fw.command->id, CommandId::kTransition);
  EXPECT_EQ(fw.command->args, std::vector<double>{1.0});
  EXPECT_EQ(fw.command->Text(), "transition fw");
  const ParseResult mc = ParseCommand("transition 0");
  ASSERT_TRUE(mc.ok()) << mc.error;
  EXPECT_EQ(mc.command->Text(), "transition mc");
  EXPECT_EQ(ParseCommand("transition up").error, "transition: argument to must be one of 'mc fw', got 'up'");
  EXPECT_NE(ParseCommand("transition 2").error.find("outside [0, 1]"), std::string::npos);
  EXPECT_NE(ParseCommand("transition").error.find("missing argument to"), std::string::npos);
  EXPECT_EQ(ArgumentHint("transition"), "transition <mc|fw>");
}

TEST(CommandGrammar, CompletionAndHints) {
  EXPECT_EQ(CompleteCommandName("ta"), std::vector<std::string>{"takeoff"});
  EXPECT_EQ(CompleteCommandName("t"), (std::vector<std::string>{"takeoff", "track", "transition"}));
  EXPECT_EQ(CompleteCommandName("").size(), CommandSpecs().size());
  EXPECT_EQ(CompleteCommandName("d"), std::vector<std::string>{"disarm"});
  EXPECT_TRUE(CompleteCommandName("x").empty());
  EXPECT_EQ(ArgumentHint("goto 1"), "goto <north_m -1000..1000> <east_m -1000..1000> <alt_m 1..120>");
  EXPECT_EQ(ArgumentHint("hover"), "hover");
  EXPECT_EQ(ArgumentHint("nope"), "");
}

}  // namespace
}  // namespace uav

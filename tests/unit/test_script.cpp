// Script parsing and conditions, and the same panels run headless with scripted input: typing
// into the command bar and clicking a tick box go through ImGui exactly as a person's would.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include <imgui.h>

#include "unit/gcs_test_util.hpp"
#include "uav/gcs/gcs_ui.hpp"
#include "uav/gcs/platform.hpp"
#include "uav/gcs/script.hpp"
#include "uav/gcs/script_input.hpp"

namespace uav::gcs {
namespace {

std::string ParseError(const std::string& text) {
  try {
    Script::Parse(text, "s.gcs");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Script, ParsesStepsAndSkipsComments) {
  const Script s = Script::Parse("# c\n\ntype takeoff 10  # go\nwait_until alt ~ 10 0.5 timeout 5\n", "s");
  ASSERT_EQ(s.steps.size(), 2u);
  EXPECT_EQ(s.steps[0].verb, "type");
  EXPECT_EQ(s.steps[0].text, "type takeoff 10");
  EXPECT_EQ(s.steps[1].line, 4);
}

TEST(Script, BadLinesNameTheLine) {
  EXPECT_EQ(ParseError("fly away"), "s.gcs:1: unknown step 'fly'");
  EXPECT_EQ(ParseError("\nwait"), "s.gcs:2: wait needs an argument");
  EXPECT_EQ(ParseError("wait -1"), "s.gcs:1: wait needs one non-negative number of seconds");
  EXPECT_EQ(ParseError("assert alt = 3"), "s.gcs:1: unknown operator '='");
  EXPECT_EQ(ParseError("assert alt ~ 3"), "s.gcs:1: '~' needs VALUE TOLERANCE");
  EXPECT_EQ(ParseError("wait_until alt > 3 timeout x"), "s.gcs:1: timeout needs a positive number of seconds");
}

TEST(Script, ConditionsOnTelemetryAndAcks) {
  GcsModel m("gcs", 1);
  m.OnHeartbeat("UAV1", 1, Hb(2, true), 0.0);
  m.OnState("UAV1", 1, StateOf(1.0, {{"alt", 9.8}, {"x", 20.2}, {"armed", 1.0}, {"task", 2}}), 0.0);
  auto eval = [&](const std::string& c) {
    std::vector<std::string> t;
    std::istringstream in(c);
    for (std::string w; in >> w;) t.push_back(w);
    return EvaluateCondition(t, m, 0.5);
  };
  EXPECT_TRUE(eval("alt ~ 10 0.5").holds);
  EXPECT_FALSE(eval("alt ~ 10 0.1").holds);
  EXPECT_TRUE(eval("alt > 9 and STATE.x >= 20.2 and task == hover and armed == 1").holds);
  EXPECT_EQ(eval("alt > 9 and x < 20").observed, "alt = 9.8 and x = 20.2");
  EXPECT_FALSE(eval("nosuch > 1").holds);
  EXPECT_EQ(eval("ack == none").holds, true);
  m.SubmitCommand("arm", 0.0);
  m.OnAck("UAV1", {"gcs", 1, "arm", CommandResult::kRejected, 0, "already armed"}, 0.1);
  EXPECT_TRUE(eval("ack == rejected and ack.reason contains already armed").holds);
  EXPECT_FALSE(eval("ack.reason lacks already armed").holds);
  EXPECT_TRUE(eval("ack.reason lacks failsafe and ack == rejected").holds);
}

// A slow build's scale stretches every wait: `timeout 2` at scale 3 gives up after 6 s, not 2.
TEST(Script, TimeoutScaleStretchesWaits) {
  GcsModel model("gcs", 1);
  UiContext ctx;
  ImGuiScriptDriver driver(ctx, nullptr);
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  ScriptRunner runner(Script::Parse("wait_until vehicles >= 1 timeout 2\n", "s"), out, 3.0);
  EXPECT_TRUE(runner.Update(model, driver, 0.0));
  EXPECT_TRUE(runner.Update(model, driver, 5.9));
  EXPECT_FALSE(runner.failed());
  EXPECT_FALSE(runner.Update(model, driver, 6.1));
  EXPECT_TRUE(runner.failed());
  std::rewind(out);
  char line[512] = {};
  std::string text;
  while (std::fgets(line, sizeof line, out)) text += line;
  std::fclose(out);
  EXPECT_NE(text.find("not true within 6 s"), std::string::npos) << text;
}

// A fake vehicle fed straight into the model, the real panels on the null platform, and the
// script driver typing and clicking.
TEST(HeadlessPanels, TypingAndClickingGoThroughImGui) {
  auto platform = MakeNullPlatform(1600, 900);
  GcsModel model("gcs", 1);
  UiContext ctx;
  ImGuiScriptDriver driver(ctx, nullptr);
  model.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  model.OnState("UAV1", 1, StateOf(1.0, {{"alt", 0.0}, {"x", 0.0}}), 0.0);
  auto frame = [&](int n) {
    for (int i = 0; i < n; ++i) {
      platform->NewFrame(1.0 / 60);
      driver.ApplyNextEvent();
      ImGui::NewFrame();
      DrawGcs(model, ctx);
      platform->Render();
    }
  };
  frame(2);
  std::string err;
  ctx.state.signal_filter = "STATE.alt";  // the tree is longer than its window: search first
  frame(1);
  ASSERT_TRUE(driver.StartClick("tick:STATE.alt", &err)) << err;
  frame(6);
  EXPECT_EQ(Keys(model.plots().ticked()), std::set<std::string>{"STATE.alt"});
  ASSERT_TRUE(driver.StartType("takeoff nan", &err)) << err;
  frame(8);
  EXPECT_TRUE(model.commands().sent().empty());
  EXPECT_NE(model.commands().error().find("not a finite number"), std::string::npos);
  // The rejected line stays in the bar for editing; typing replaces it (Ctrl+A first).
  EXPECT_EQ(ctx.state.command_text, "takeoff nan");
  ASSERT_TRUE(driver.StartType("arm", &err)) << err;
  frame(8);
  ASSERT_EQ(model.commands().sent().size(), 1u);
  EXPECT_EQ(model.commands().sent().back().text, "arm");
  EXPECT_EQ(model.commands().TakeOutgoing().size(), 1u);
  // Button with confirmation.
  ASSERT_TRUE(driver.StartClick("button:land", &err)) << err;
  frame(6);
  EXPECT_EQ(model.commands().sent().size(), 1u);  // not yet: asks first
  ASSERT_TRUE(driver.StartClick("confirm", &err)) << err;
  frame(6);
  EXPECT_EQ(model.commands().sent().back().text, "land");
  EXPECT_FALSE(driver.StartClick("no-such-widget", &err));
  EXPECT_EQ(err, "no widget 'no-such-widget' on screen");
}

}  // namespace
}  // namespace uav::gcs

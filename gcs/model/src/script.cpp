#include "uav/gcs/script.hpp"

#include "script_conditions.hpp"
#include "uav/shared/text_file.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <cctype>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace uav::gcs {
using script_detail::Clauses;
using script_detail::Format;
using script_detail::ToNumber;

namespace {

// The tick box of a signal ("alt" is STATE's): "tick:STATE.alt".
std::string TickLabel(const std::string& signal) {
  const auto s = FindSignal(signal);
  return "tick:" + (s ? Key(*s) : signal);
}


}  // namespace

Script Script::Parse(const std::string& text, const std::string& name) {
  static const std::set<std::string> kVerbs = {"type", "click", "tick", "select", "wait", "wait_until", "assert",
                                               "screenshot", "echo", "set", "map_click", "map_right_click",
                                               "map_drag", "map_zoom", "video_click", "video_right_click",
                                               "video_drag", "plot_zoom", "plot_drag", "plot_hover",
                                               "livemap_zoom", "livemap_drag", "key", "seek", "pause", "play"};
  static const std::map<std::string, std::size_t> kNumericArgs = {
      {"video_click", 2}, {"video_right_click", 2}, {"video_drag", 4}, {"plot_zoom", 2}, {"plot_drag", 3},
      {"plot_hover", 2}, {"livemap_zoom", 1}, {"livemap_drag", 4}};
  Script s;
  s.name = name;
  std::istringstream lines(text);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    ++n;
    if (auto h = line.find('#'); h != std::string::npos) line = line.substr(0, h);
    std::istringstream words(line);
    ScriptStep st;
    st.line = n;
    if (!(words >> st.verb)) continue;
    for (std::string w; words >> w;) st.args.push_back(w);
    const auto first = line.find_first_not_of(" \t");
    const auto last = line.find_last_not_of(" \t\r");
    st.text = line.substr(first, last - first + 1);
    auto fail = [&](const std::string& why) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": " + why);
    };
    if (!kVerbs.count(st.verb)) fail("unknown step '" + st.verb + "'");
    const bool needs_args = st.verb != "echo" && st.verb != "pause" && st.verb != "play";
    if (needs_args && st.args.empty()) fail(st.verb + " needs an argument");
    double d;
    if (st.verb == "wait" && (st.args.size() != 1 || !ToNumber(st.args[0], &d) || d < 0))
      fail("wait needs one non-negative number of seconds");
    if (st.verb == "set" && st.args.size() < 2) fail("set needs a widget label and a value");
    const std::size_t map_args = st.verb == "map_drag" ? 4 : st.verb == "map_zoom" ? 3 : 2;
    if (st.verb.rfind("map_", 0) == 0) {
      if (st.args.size() != map_args) fail(st.verb + " needs " + std::to_string(map_args) + " numbers (north east [m])");
      for (const auto& a : st.args)
        if (!ToNumber(a, &d)) fail(st.verb + ": '" + a + "' is not a number");
    }
    if (auto it = kNumericArgs.find(st.verb); it != kNumericArgs.end()) {
      if (st.args.size() != it->second) fail(st.verb + " needs " + std::to_string(it->second) + " numbers");
      for (const auto& a : st.args)
        if (!ToNumber(a, &d) || !std::isfinite(d)) fail(st.verb + ": '" + a + "' is not a number");
    }
    if (st.verb == "seek" && (st.args.size() != 1 || !ToNumber(st.args[0], &d) || d < 0))
      fail("seek needs one non-negative number of seconds from the start of the log");
    if (st.verb == "key" && st.args.size() != 1) fail("key needs one chord, e.g. ctrl+h or escape");
    if (st.verb == "wait_until" || st.verb == "assert") {
      std::vector<std::string> cond = st.args;
      if (st.verb == "wait_until" && cond.size() >= 2 && cond[cond.size() - 2] == "timeout") {
        if (!ToNumber(cond.back(), &d) || d <= 0) fail("timeout needs a positive number of seconds");
        cond.resize(cond.size() - 2);
      }
      try {
        Clauses(cond);
      } catch (const std::exception& e) {
        fail(e.what());
      }
    }
    s.steps.push_back(std::move(st));
  }
  return s;
}

Script Script::LoadFile(const std::string& path) {
  return Parse(ReadTextFile(path, "script"), path);
}

void ScriptRunner::Pass(const ScriptStep& s, double now, const std::string& detail) {
  std::fprintf(out_, "[%7.2fs] ok    %3d: %s%s%s\n", now - script_start_, s.line, s.text.c_str(),
               detail.empty() ? "" : "  -> ", detail.c_str());
  std::fflush(out_);
  ++passed_;
  ++index_;
  step_started_ = false;
}

void ScriptRunner::Fail(const GcsModel& model, const ScriptStep& s, double now, const std::string& why) {
  std::fprintf(out_, "[%7.2fs] FAIL  %3d: %s  -> %s\n", now - script_start_, s.line, s.text.c_str(),
               why.c_str());
  // The newest warnings, and the newest messages of any kind: what the operator would have read.
  constexpr int kWarningsShown = 3, kLinesShown = 8;
  std::vector<const LogLine*> warnings;
  const auto& lines = model.log().lines();
  int shown = 0;
  for (auto it = lines.rbegin(); it != lines.rend() && static_cast<int>(warnings.size()) < kWarningsShown + kLinesShown; ++it)
    if (it->severity <= Severity::kWarning || shown++ < kLinesShown) warnings.push_back(&*it);
  for (auto it = warnings.rbegin(); it != warnings.rend(); ++it)
    std::fprintf(out_, "           log: [%s] %s\n", (*it)->vehicle_id.c_str(), (*it)->text.c_str());
  std::fflush(out_);
  failed_ = true;
}

bool ScriptRunner::Update(GcsModel& model, ScriptDriver& driver, double now) {
  if (script_start_ < 0) script_start_ = now;
  if (finished()) return false;
  const ScriptStep& s = script_.steps[index_];
  const bool first = !step_started_;
  if (first) {
    step_started_ = true;
    step_start_ = now;
  }
  std::string err;
  const std::string joined = [&] {
    std::string j;
    for (const auto& a : s.args) j += (j.empty() ? "" : " ") + a;
    return j;
  }();
  if (s.verb == "echo") {
    Pass(s, now, "");
  } else if (s.verb == "seek" || s.verb == "pause" || s.verb == "play") {
    if (!replay_) {
      Fail(model, s, now, s.verb + " needs a replay (uav-gcs --replay LOG)");
    } else {
      if (s.verb == "seek") replay_->Seek(std::atof(s.args[0].c_str()));
      else if (s.verb == "pause") replay_->Pause();
      else replay_->Play();
      char buf[64];
      std::snprintf(buf, sizeof buf, "replay at %.2f s of %.2f s", replay_->position(), replay_->duration());
      Pass(s, now, buf);
    }
  } else if (s.verb == "wait") {
    if (now - step_start_ >= std::atof(s.args[0].c_str())) Pass(s, now, "");
  } else if (s.verb == "type" || s.verb == "click" || s.verb == "tick" || s.verb == "select" ||
             s.verb == "set" || s.verb.rfind("map_", 0) == 0 || s.verb.rfind("video_", 0) == 0 ||
             s.verb.rfind("plot_", 0) == 0 || s.verb.rfind("livemap_", 0) == 0 || s.verb == "key") {
    if (first) {
      const std::string label = s.verb == "tick" ? TickLabel(s.args[0])
                              : s.verb == "select" ? "vehicle:" + s.args[0] : joined;
      std::vector<double> xy;
      for (const auto& a : s.args) xy.push_back(std::atof(a.c_str()));
      using G = ScriptDriver::Gesture;
      bool ok;
      tick_searched_ = false;
      // A tick searches the signal first, as an operator would in a tree longer than its window.
      if (s.verb == "tick") ok = driver.StartSet("signals:search", label.substr(5), &err);
      else if (s.verb == "type") ok = driver.StartType(joined, &err);
      else if (s.verb == "set") ok = driver.StartSet(s.args[0], joined.substr(s.args[0].size() + 1), &err);
      else if (s.verb == "map_click") ok = driver.StartMapClick(xy[0], xy[1], false, &err);
      else if (s.verb == "map_right_click") ok = driver.StartMapClick(xy[0], xy[1], true, &err);
      else if (s.verb == "map_drag") ok = driver.StartMapDrag(xy[0], xy[1], xy[2], xy[3], &err);
      else if (s.verb == "map_zoom") ok = driver.StartMapZoom(xy[0], xy[1], static_cast<int>(xy[2]), &err);
      else if (s.verb == "video_click" || s.verb == "video_right_click")
        ok = driver.StartGesture("video:image", s.verb == "video_click" ? G::kClick : G::kRightClick, xy[0], xy[1], 0, 0, 0, &err);
      else if (s.verb == "video_drag") ok = driver.StartGesture("video:image", G::kDrag, xy[0], xy[1], xy[2], xy[3], 0, &err);
      else if (s.verb.rfind("plot_", 0) == 0) {
        const std::string canvas = "plot:" + s.args[0] + ":canvas";
        if (s.verb == "plot_zoom") ok = driver.StartGesture(canvas, G::kWheel, 0.5, 0.5, 0, 0, static_cast<int>(xy[1]), &err);
        else if (s.verb == "plot_drag") ok = driver.StartGesture(canvas, G::kDrag, xy[1], 0.5, xy[2], 0.5, 0, &err);
        else ok = driver.StartGesture(canvas, G::kHover, xy[1], 0.5, 0, 0, 0, &err);
      } else if (s.verb == "livemap_zoom") ok = driver.StartGesture("livemap", G::kWheel, 0.5, 0.5, 0, 0, static_cast<int>(xy[0]), &err);
      else if (s.verb == "livemap_drag") ok = driver.StartGesture("livemap", G::kDrag, xy[0], xy[1], xy[2], xy[3], 0, &err);
      else if (s.verb == "key") {
        const std::string chord = s.args[0];
        const bool ctrl = chord.rfind("ctrl+", 0) == 0;
        ok = driver.StartKey(ctrl ? chord.substr(5) : chord, ctrl, &err);
      }
      else ok = driver.StartClick(label, &err);
      if (!ok) Fail(model, s, now, err);
    } else if (s.verb == "tick" && !tick_searched_ && !driver.InputPending()) {
      tick_searched_ = true;
      if (!driver.StartClick(TickLabel(s.args[0]), &err))
        Fail(model, s, now, err);
    } else if (!driver.InputPending()) {
      Pass(s, now, s.verb == "type" && !model.commands().error().empty()
                       ? "command bar says: " + model.commands().error() : "");
    } else if (now - step_start_ > 10.0 * timeout_scale_) {
      Fail(model, s, now, "input was not consumed within " + Format(10.0 * timeout_scale_) + " s");
    }
  } else if (s.verb == "screenshot") {
    const int r = driver.Screenshot(s.args[0], &err);
    if (r > 0) Pass(s, now, "saved " + s.args[0]);
    else if (r < 0) Fail(model, s, now, err);
  } else {  // wait_until, assert
    std::vector<std::string> cond = s.args;
    double timeout = 30.0;
    if (s.verb == "wait_until" && cond.size() >= 2 && cond[cond.size() - 2] == "timeout") {
      timeout = std::atof(cond.back().c_str());
      cond.resize(cond.size() - 2);
    }
    timeout *= timeout_scale_;
    const ConditionResult r = EvaluateCondition(cond, model, now, replay_);
    if (!r.error.empty()) Fail(model, s, now, r.error);
    else if (r.holds) Pass(s, now, r.observed);
    else if (s.verb == "assert") Fail(model, s, now, "observed " + r.observed);
    else if (now - step_start_ > timeout)
      Fail(model, s, now, "not true within " + Format(timeout) + " s; observed " + r.observed);
  }
  return !finished();
}

}  // namespace uav::gcs

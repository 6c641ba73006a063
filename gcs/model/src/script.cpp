#include "uav/gcs/script.hpp"

#include "uav/shared/text_file.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <cctype>
#include <map>
#include <sstream>
#include <stdexcept>

namespace uav::gcs {
namespace {

// The tick box of a signal ("alt" is STATE's): "tick:STATE.alt".
std::string TickLabel(const std::string& signal) {
  const auto s = FindSignal(signal);
  return "tick:" + (s ? Key(*s) : signal);
}

const std::set<std::string> kOps = {"==", "!=", "<", "<=", ">", ">=", "~", "contains", "lacks"};

bool ToNumber(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && std::isfinite(*v);
}

std::string Format(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  std::string s = buf;
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

// Splits a condition into clauses of {lhs, op, rhs[, tol]}; throws on malformed input.
std::vector<std::vector<std::string>> Clauses(const std::vector<std::string>& tokens) {
  std::vector<std::vector<std::string>> out(1);
  for (const auto& t : tokens) {
    if (t == "and") out.emplace_back();
    else out.back().push_back(t);
  }
  for (const auto& c : out) {
    if (c.size() < 3) throw std::runtime_error("condition needs LHS OP RHS");
    if (!kOps.count(c[1])) throw std::runtime_error("unknown operator '" + c[1] + "'");
    const std::size_t want = c[1] == "~" ? 4 : 3;
    if (c[1] != "contains" && c[1] != "lacks" && c.size() != want)
      throw std::runtime_error(c[1] == "~" ? "'~' needs VALUE TOLERANCE" : "too many words in clause");
    double d;
    if (c[1] == "~" && (!ToNumber(c[2], &d) || !ToNumber(c[3], &d)))
      throw std::runtime_error("'~' needs numeric VALUE and TOLERANCE");
  }
  return out;
}

// Value of a name: number (is_number) or string.
bool Lookup(const std::string& name, const GcsModel& m, const ReplayControl* replay, double now, double* num,
            std::string* str, bool* is_number) {
  const VehicleModel* v = m.selected();
  // "ack": this GCS's newest command; "vehicle.ack": what the vehicle newest did on its own.
  const bool own = name.rfind("vehicle.", 0) == 0;
  const SentCommand* last = nullptr;
  for (auto it = m.commands().sent().rbegin(); it != m.commands().sent().rend() && !last; ++it)
    if (it->vehicle_initiated == own) last = &*it;
  const std::string key = own ? name.substr(8) : name;
  *is_number = false;
  if (key == "ack") return *str = last && last->last_ack ? std::string(Name(last->last_ack->result)) : "none", true;
  if (key == "ack.reason") return *str = last && last->last_ack ? last->last_ack->reason : "", true;
  if (key == "ack.command") return *str = last && last->last_ack ? last->last_ack->command : "", true;
  if (name == "error") return *str = m.commands().error(), true;
  if (name == "survey.problem") return *str = m.missions().planner().problem(), true;
  if (name == "upload") {
    using State = waypoints::MissionUploader::State;
    if (!v || !v->upload) return *str = "none", true;
    const State st = v->upload->state();
    return *str = st == State::kSending ? "sending" : st == State::kAccepted ? "accepted"
                : st == State::kRejected ? "rejected" : "failed", true;
  }
  if (name == "upload.reason") return *str = v && v->upload ? v->upload->reason() : m.missions().error(), true;
  if (name == "task") return *str = !v ? "none" : v->task ? std::string(Name(*v->task)) : "unknown", true;
  if (name == "selected") return *str = m.selected_id(), true;
  if (name == "link") return *str = v && v->LinkUp(now, m.telemetry_params()) ? "up" : "down", true;
  if (name == "replay.damage") return *str = replay ? replay->damage() : "", true;
  if (name == "track.method" || name == "track.state" || name == "track.error") {
    if (name == "track.error") return *str = m.video().error(), true;
    if (name == "track.method") {
      if (!v || !v->track_target) return *str = "none", true;
      const auto k = v->track_target->method;
      return *str = k == TrackTarget::kDrag ? "drag" : k == TrackTarget::kFourClicks ? "four_clicks" : "cancel", true;
    }
    if (!v || !v->track) return *str = "none", true;
    const auto k = v->track->state;
    return *str = k == TrackStatus::kTracking   ? "tracking"
                  : k == TrackStatus::kLost     ? "lost"
                  : k == TrackStatus::kRejected ? "rejected"
                                                : "idle",
           true;
  }
  if (name == "log") {
    str->clear();
    for (const auto& l : m.log().lines()) *str += l.vehicle_id + ": " + l.text + "\n";
    return true;
  }
  *is_number = true;
  if (key == "ack.percent") return *num = last && last->last_ack ? last->last_ack->percent : -1, true;
  if (name == "tries") return *num = last ? last->tries : 0, true;
  if (name == "survey.vertices") return *num = static_cast<double>(m.missions().planner().polygon().size()), true;
  if (name == "survey.images") return *num = m.missions().planner().plan() ? static_cast<double>(m.missions().planner().plan()->captures.size()) : 0.0, true;
  if (name == "survey.lines") return *num = m.missions().planner().plan() ? m.missions().planner().plan()->lines : 0, true;
  if (name == "survey.altitude") return *num = m.missions().planner().plan() ? m.missions().planner().plan()->altitude_m : 0.0, true;
  if (name == "survey.ok") return *num = m.missions().planner().plan() && m.missions().planner().problem().empty() ? 1.0 : 0.0, true;
  if (name == "video.frames") return *num = v ? static_cast<double>(v->video.frames) : 0.0, true;
  if (name == "video.rejected") return *num = v ? static_cast<double>(v->video.rejected) : 0.0, true;
  if (name == "video.width") return *num = v ? v->video.width : 0.0, true;
  if (name == "video.source_width") return *num = v ? v->video.source_width : 0.0, true;
  if (name == "mission.items") return *num = v && v->mission ? static_cast<double>(v->mission->items.size()) : 0.0, true;
  if (name == "basemap.width") return *num = m.basemap().image() ? m.basemap().image()->source_width : 0.0, true;
  if (name == "livemap.tiles") return *num = v ? static_cast<double>(v->live_map.tiles.size()) : 0.0, true;
  if (name == "livemap.received") return *num = v ? static_cast<double>(v->live_map.received) : 0.0, true;
  if (name == "download.offered") return *num = v ? static_cast<double>(v->files.offers().size()) : 0.0, true;
  if (name == "download.saved") {
    int n = 0;
    if (v)
      for (const auto& [id, path] : v->saved) n += !path.empty();
    return *num = n, true;
  }
  if (name == "vehicles") return *num = static_cast<double>(m.vehicles().size()), true;
  if (name == "plot_panels") return *num = static_cast<double>(m.plots().specs().size()), true;
  if (name == "plot.window") return *num = m.plots().window(), true;
  if (name == "plot.held") return *num = m.plots().hold() ? 1.0 : 0.0, true;
  if (name.size() > 5 && name.rfind("plot", 0) == 0 && std::isdigit(static_cast<unsigned char>(name[4]))) {
    const std::size_t dot = name.find('.');
    const int index = std::atoi(name.substr(4, dot - 4).c_str()) - 1;
    if (dot == std::string::npos || index < 0 || index >= static_cast<int>(m.plots().specs().size())) return false;
    const std::string what = name.substr(dot + 1);
    int n = 0;
    for (const auto& [key, axis] : m.plots().specs()[index].signals) n += what == "signals" || axis == PlotAxis::kRight;
    if (what != "signals" && what != "right") return false;
    return *num = n, true;
  }
  // Depth from motion over the live video: its cells known, and those that are obstacles.
  if (name == "depth.known" || name == "depth.obstacles") {
    const DepthGrid* g = v ? v->DepthGridOver(v->video, now, m.obstacles().params()) : nullptr;
    int n = 0;
    if (g)
      for (const DepthCell& c : g->cells)
        n += name == "depth.known" ? c.state != CellState::kUnknown : c.state == CellState::kObstacle;
    return *num = n, true;
  }
  // Active stereo over the live video: its dots and clusters (0 when none is drawn).
  if (name == "asv.points" || name == "asv.clusters") {
    const ActiveStereoReport* r = v ? v->ActiveStereoOver(v->video, now, m.obstacles().params()) : nullptr;
    return *num = !r ? 0.0 : name == "asv.points" ? static_cast<double>(r->dots.size()) : static_cast<double>(r->clusters.size()), true;
  }
  if (name == "video.frozen") return *num = m.video().frozen() ? 1.0 : 0.0, true;
  if (name == "track.sent") return *num = v ? static_cast<double>(v->track_targets_sent) : 0.0, true;
  if (name.rfind("track.", 0) == 0) {
    if (!v) return false;
    if (name == "track.cx" || name == "track.cy") {
      if (!v->track) return false;
      return *num = name == "track.cx" ? v->track->center_x : v->track->center_y, true;
    }
    if (!v->track_target) return false;
    const TrackTarget& t = *v->track_target;
    if (name == "track.x") return *num = t.x, true;
    if (name == "track.y") return *num = t.y, true;
    if (name == "track.w") return *num = t.width, true;
    if (name == "track.h") return *num = t.height, true;
    return false;
  }
  if (name == "plots") return *num = static_cast<double>(m.plots().ticked().size()), true;
  if (name == "sent") return *num = static_cast<double>(m.commands().sent().size()), true;
  if (name == "gave_up") {
    int n = 0;
    for (const auto& c : m.commands().sent()) n += c.gave_up;
    return *num = n, true;
  }
  if (!v) return false;
  // Power lines: the warning (0/1), wires in the newest report, and how many were ranged.
  if (name == "wires.warning") return *num = v->wire_warning ? 1.0 : 0.0, true;
  if (name == "wires.seen" || name == "wires.ranged") {
    if (!v->power_lines) return false;
    int n = 0;
    for (const PowerLine& w : v->power_lines->wires) n += name == "wires.seen" || w.ranged();
    return *num = n, true;
  }
  if (name == "replay.position") return replay ? (*num = replay->position(), true) : false;
  if (name == "replay.events") return replay ? (*num = static_cast<double>(replay->dispatched()), true) : false;
  if (name == "replay.paused") return replay ? (*num = replay->paused() ? 1.0 : 0.0, true) : false;
  if (name == "replay.speed") return replay ? (*num = replay->speed(), true) : false;
  // A telemetry signal, through the signal tables: "alt" is STATE's, "HEARTBEAT.task" another group's.
  const auto signal = FindSignal(name);
  if (!signal) return false;
  const auto value = v->Latest(*signal);
  if (!value) return false;
  *num = *value;
  return true;
}

}  // namespace

ConditionResult EvaluateCondition(const std::vector<std::string>& tokens, const GcsModel& model, double now,
                                  const ReplayControl* replay) {
  ConditionResult r;
  r.holds = true;
  std::vector<std::vector<std::string>> clauses;
  try {
    clauses = Clauses(tokens);
  } catch (const std::exception& e) {
    r.holds = false;
    r.error = e.what();
    return r;
  }
  for (const auto& c : clauses) {
    double lv = 0;
    std::string ls;
    bool lnum = false;
    if (!Lookup(c[0], model, replay, now, &lv, &ls, &lnum)) {
      r.holds = false;
      r.observed += (r.observed.empty() ? "" : " and ") + c[0] + " = (no value yet)";
      continue;
    }
    std::string rhs = c[2];
    for (std::size_t i = 3; (c[1] == "contains" || c[1] == "lacks") && i < c.size(); ++i) rhs += " " + c[i];
    double rv = 0;
    bool holds = false;
    if (c[1] == "contains" || c[1] == "lacks") {
      holds = ((lnum ? Format(lv) : ls).find(rhs) != std::string::npos) == (c[1] == "contains");
    } else if (lnum && ToNumber(rhs, &rv)) {
      const std::string& op = c[1];
      double tol = 0;
      if (op == "~") ToNumber(c[3], &tol);
      holds = op == "==" ? lv == rv : op == "!=" ? lv != rv : op == "<" ? lv < rv
            : op == "<=" ? lv <= rv : op == ">" ? lv > rv : op == ">=" ? lv >= rv
            : std::abs(lv - rv) <= tol;
    } else if (c[1] == "==" || c[1] == "!=") {
      holds = (c[1] == "==") == ((lnum ? Format(lv) : ls) == rhs);
    } else {
      r.error = "operator " + c[1] + " needs numbers on both sides of '" + c[0] + "'";
    }
    if (!holds) r.holds = false;
    if (c[0] != "log")
      r.observed += (r.observed.empty() ? "" : " and ") + c[0] + " = " + (lnum ? Format(lv) : "'" + ls + "'");
  }
  if (!r.error.empty()) r.holds = false;
  return r;
}

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

void ScriptRunner::Fail(const ScriptStep& s, double now, const std::string& why) {
  std::fprintf(out_, "[%7.2fs] FAIL  %3d: %s  -> %s\n", now - script_start_, s.line, s.text.c_str(),
               why.c_str());
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
      Fail(s, now, s.verb + " needs a replay (uav-gcs --replay LOG)");
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
      if (!ok) Fail(s, now, err);
    } else if (s.verb == "tick" && !tick_searched_ && !driver.InputPending()) {
      tick_searched_ = true;
      if (!driver.StartClick(TickLabel(s.args[0]), &err))
        Fail(s, now, err);
    } else if (!driver.InputPending()) {
      Pass(s, now, s.verb == "type" && !model.commands().error().empty()
                       ? "command bar says: " + model.commands().error() : "");
    } else if (now - step_start_ > 10.0 * timeout_scale_) {
      Fail(s, now, "input was not consumed within " + Format(10.0 * timeout_scale_) + " s");
    }
  } else if (s.verb == "screenshot") {
    const int r = driver.Screenshot(s.args[0], &err);
    if (r > 0) Pass(s, now, "saved " + s.args[0]);
    else if (r < 0) Fail(s, now, err);
  } else {  // wait_until, assert
    std::vector<std::string> cond = s.args;
    double timeout = 30.0;
    if (s.verb == "wait_until" && cond.size() >= 2 && cond[cond.size() - 2] == "timeout") {
      timeout = std::atof(cond.back().c_str());
      cond.resize(cond.size() - 2);
    }
    timeout *= timeout_scale_;
    const ConditionResult r = EvaluateCondition(cond, model, now, replay_);
    if (!r.error.empty()) Fail(s, now, r.error);
    else if (r.holds) Pass(s, now, r.observed);
    else if (s.verb == "assert") Fail(s, now, "observed " + r.observed);
    else if (now - step_start_ > timeout)
      Fail(s, now, "not true within " + Format(timeout) + " s; observed " + r.observed);
  }
  return !finished();
}

}  // namespace uav::gcs

// Script conditions: the value of each name a script may test, and the clauses that test them.
#include "script_conditions.hpp"

#include "uav/shared/decimal.hpp"

#include <cmath>
#include <set>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "uav/gcs/script.hpp"

namespace uav::gcs {
namespace script_detail {

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

}  // namespace script_detail

using script_detail::Clauses;
using script_detail::Format;
using script_detail::ToNumber;

namespace {

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
  if (name == "plan.problem") {  // the first thing the vehicle would refuse, as it will say it
    const auto& mi = m.missions();
    const EditorCheck c = mi.editor().Check(mi.planner(), mi.planner().origin(), m.MissionLimits());
    return *str = !c.mission ? c.error : c.problems.empty() ? "" : c.problems.front().text, true;
  }
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
  if (name == "plan.items") return *num = static_cast<double>(m.missions().editor().items().size()), true;
  if (name == "plan.fences") return *num = static_cast<double>(m.missions().editor().fences.size()), true;
  if (name == "plan.rally") return *num = static_cast<double>(m.missions().editor().rally.size()), true;
  if (name == "plan.problems") {
    const auto& mi = m.missions();
    return *num = static_cast<double>(mi.editor().Check(mi.planner(), mi.planner().origin(), m.MissionLimits()).problems.size()), true;
  }
  if (name == "plan.flown") return *num = m.FlownMissionRow() + 1.0, true;  // 1-based, 0: none
  // Row N's altitude, speed, hold time (plan.alt.3).
  for (const char* field : {"plan.alt.", "plan.speed.", "plan.hold."})
    if (name.rfind(field, 0) == 0) {
      const auto row = ParseDecimal(name.substr(std::string(field).size()));
      const auto& items = m.missions().editor().items();
      if (!row || *row < 1 || *row > static_cast<double>(items.size())) return false;
      const PlanItem& it = items[static_cast<std::size_t>(*row) - 1];
      return *num = field[5] == 'a' ? it.altitude_m : field[5] == 's' ? it.speed_m_s : it.hold_s, true;
    }
  if (name == "plan.selected") return *num = m.missions().editor().selected + 1.0, true;  // 1-based, 0: none
  if (name == "survey.vertices") return *num = static_cast<double>(m.missions().planner().polygon().size()), true;
  if (name == "survey.images") return *num = m.missions().planner().plan() ? static_cast<double>(m.missions().planner().plan()->captures.size()) : 0.0, true;
  if (name == "survey.lines") return *num = m.missions().planner().plan() ? m.missions().planner().plan()->lines : 0, true;
  if (name == "survey.altitude") return *num = m.missions().planner().plan() ? m.missions().planner().plan()->altitude_m : 0.0, true;
  if (name == "survey.speed") return *num = m.missions().planner().params().speed_m_s, true;
  if (name == "survey.turn_radius") return *num = m.missions().planner().params().turn_radius_m, true;
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
  if (name == "link.lost") return *num = v ? static_cast<double>(v->sequence_gaps) : 0.0, true;
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
  // A parameter's value as the vehicle last reported it (param.ctl_speed_max_xy).
  if (name.rfind("param.", 0) == 0) {
    const auto* table = v ? &v->reports.Get<ParameterTable>() : nullptr;
    const ParameterEntry* e = table && table->newest ? table->newest->Find(name.substr(6)) : nullptr;
    return e ? (*num = e->value, true) : false;
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
    const std::optional<PowerLines>& lines = v->reports.Get<PowerLines>().newest;
    if (!lines) return false;
    int n = 0;
    for (const PowerLine& w : lines->wires) n += name == "wires.seen" || w.ranged();
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

}  // namespace uav::gcs

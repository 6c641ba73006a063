#pragma once
// Operator scripts for the headless GCS (and the window, for end-to-end tests). One step a line:
//   type TEXT                 type TEXT into the command bar and press Enter
//   click LABEL               click the widget registered under LABEL (buttons, list entries)
//   tick SIGNAL               search the telemetry tree for SIGNAL, then tick it into the plot
//                             (click "tick:STATE.SIGNAL")
//   set LABEL VALUE           click the input field LABEL, select all, type VALUE, Enter
//   map_click N E             left click on the map at north N, east E [m from the map origin]
//   map_right_click N E       right click there (deletes a survey vertex)
//   map_drag N1 E1 N2 E2      press at the first point, drag to the second, release
//   map_zoom N E STEPS        mouse wheel STEPS notches over the map at N E (+ in, - out)
//   video_click FX FY         click the video picture at (FX, FY), fractions of its width/height
//   video_right_click FX FY
//   video_drag FX1 FY1 FX2 FY2  press, drag, release on the video picture
//   plot_zoom N STEPS         mouse wheel over plot N's canvas
//   plot_drag N FX1 FX2       drag across plot N's canvas (pans the time axis)
//   plot_hover N FX           hold the pointer over plot N at FX (the readout shows)
//   livemap_zoom STEPS        mouse wheel over the live map's centre
//   livemap_drag FX1 FY1 FX2 FY2
//   key CHORD                 a key, e.g. ctrl+h, ctrl+k, escape
//   select VEHICLE            pick the vehicle the panels show (click "vehicle:ID")
//   wait SECONDS              let time pass
//   wait_until COND [timeout SECONDS]   (default timeout 30 s)
//   assert COND
//   seek T                    replay only: jump to T seconds from the start of the log
//   pause / play              replay only: stop or go on
//   screenshot FILE           window mode only
//   echo TEXT
// COND is "LHS OP RHS" clauses joined by "and"; OP is == != < <= > >= contains, or
// "~ VALUE TOL" (|LHS - VALUE| <= TOL). LHS is a signal of the selected vehicle ("alt",
// "STATE.x", "HEARTBEAT...") or one of: ack ack.reason ack.command ack.percent (this GCS's newest
// command; vehicle.ack ... for what the vehicle did on its own, a failsafe) tries error task
// armed vehicles selected plots link link.lost sent gave_up log survey.vertices survey.images
// survey.lines survey.altitude survey.ok survey.problem upload upload.reason mission.items
// plan.items plan.selected plan.flown plan.problems plan.problem plan.alt.N plan.speed.N plan.hold.N
// video.frames video.rejected video.frozen basemap.width livemap.tiles livemap.received download.offered
// download.saved plot_panels plot.window plot.held plotN.signals plotN.right track.sent track.x
// track.y track.w track.h track.method track.state track.cx track.cy track.error; in a replay
// also replay.position replay.events replay.paused replay.speed replay.damage.
// '#' starts a comment.
#include <cstdio>
#include <string>
#include <vector>

#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/replay_control.hpp"

namespace uav::gcs {

struct ScriptStep {
  int line = 0;
  std::string verb;
  std::vector<std::string> args;
  std::string text;  // the line as written, without the comment
};

struct Script {
  std::string name;
  std::vector<ScriptStep> steps;
  // Throws std::runtime_error "NAME:LINE: ..." for an unknown verb, a missing or bad argument,
  // or a malformed condition.
  static Script Parse(const std::string& text, const std::string& name);
  static Script LoadFile(const std::string& path);
};

struct ConditionResult {
  bool holds = false;
  std::string observed;  // "alt = 9.93 and ack = completed"
  std::string error;     // set when a name is unknown
};
ConditionResult EvaluateCondition(const std::vector<std::string>& tokens, const GcsModel& model, double now,
                                  const ReplayControl* replay = nullptr);

// What a script needs from the user interface: real input delivered to the panels.
class ScriptDriver {
 public:
  virtual ~ScriptDriver() = default;
  virtual bool StartType(const std::string& text, std::string* error) = 0;
  virtual bool StartClick(const std::string& label, std::string* error) = 0;
  virtual bool StartSet(const std::string& label, const std::string& text, std::string* error) = 0;
  virtual bool StartMapClick(double north, double east, bool right, std::string* error) = 0;
  virtual bool StartMapDrag(double n1, double e1, double n2, double e2, std::string* error) = 0;
  virtual bool StartMapZoom(double north, double east, int steps, std::string* error) = 0;
  // Pointer gestures on a widget registered under `label`, at fractions of its rectangle.
  enum class Gesture { kClick, kRightClick, kDrag, kWheel, kHover };
  virtual bool StartGesture(const std::string& label, Gesture g, double fx1, double fy1, double fx2, double fy2,
                            int steps, std::string* error) = 0;
  // A key press, optionally with Ctrl: a letter or "escape".
  virtual bool StartKey(const std::string& key, bool ctrl, std::string* error) = 0;
  virtual bool InputPending() const = 0;
  // 1: saved; 0: pending (call again next frame); -1: failed, *error says why.
  virtual int Screenshot(const std::string& path, std::string* error) = 0;
};

class ScriptRunner {
 public:
  // timeout_scale multiplies every wait (wait_until's timeout, input consumption): a build that
  // runs several times slower, as under sanitizers, waits as long in its own time.
  ScriptRunner(Script script, std::FILE* out, double timeout_scale = 1.0)
      : script_(std::move(script)), out_(out), timeout_scale_(timeout_scale) {}
  // Advances the script; call once per frame. Returns false when it has finished or failed.
  bool Update(GcsModel& model, ScriptDriver& driver, double now);
  void SetReplay(ReplayControl* replay) { replay_ = replay; }
  bool failed() const { return failed_; }
  bool finished() const { return index_ >= script_.steps.size() || failed_; }
  int passed() const { return passed_; }

 private:
  void Pass(const ScriptStep& s, double now, const std::string& detail);
  // Prints why the step failed and the vehicle's last warnings, which often say the cause.
  void Fail(const GcsModel& model, const ScriptStep& s, double now, const std::string& why);

  Script script_;
  std::FILE* out_;
  double timeout_scale_ = 1.0;
  ReplayControl* replay_ = nullptr;
  bool tick_searched_ = false;  // a tick step has typed its signal into the search box
  std::size_t index_ = 0;
  bool step_started_ = false;
  double step_start_ = 0.0;
  double script_start_ = -1.0;
  bool failed_ = false;
  int passed_ = 0;
};

}  // namespace uav::gcs

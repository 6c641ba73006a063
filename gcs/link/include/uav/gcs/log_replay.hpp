#pragma once
// Plays an onboard LCM event log (uav-onboard --log-dir writes events_<utime>.lcmlog) into the
// GCS model through the same decoding as the live link. Time is the vehicle's clock (the newest
// vehicle_state_t.utime in the log), so 1x replays the flight as long as it was flown, whatever
// speed the simulator ran at. Nothing is ever sent. Seeking back starts again from the log's
// beginning (the model accumulates history), through `reset`, which must hand back a fresh
// link over a fresh model.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lcm {
class LogFile;
}

namespace uav::gcs {

class GcsLink;

class LogReplay {
 public:
  static constexpr double kMinSpeed = 0.1, kMaxSpeed = 10.0;

  // Reads the log's index (every event's place and time). Throws std::runtime_error naming the
  // file when it cannot be opened or holds no readable event. A damaged or truncated log is
  // indexed up to the damage; damage() says where.
  LogReplay(const std::string& path, std::function<GcsLink&()> reset);
  ~LogReplay();

  // Advances the replay clock by `wall_seconds` times the speed (nothing while paused) and
  // dispatches the events up to it. Returns the number dispatched.
  int Advance(double wall_seconds);
  // Jumps to `t` seconds from the start (clamped to the log); back means from the beginning.
  void Seek(double t);
  void Pause() { paused_ = true; }
  void Play() { paused_ = false; }
  // Refused (false) outside kMinSpeed..kMaxSpeed or not finite.
  bool SetSpeed(double speed);

  double position() const { return position_; }   // [s] from the start of the log
  double duration() const { return duration_; }   // [s]
  double now() const { return start_ + position_; }  // the model's clock: vehicle time [s]
  bool paused() const { return paused_; }
  bool finished() const { return next_ >= events_.size(); }
  double speed() const { return speed_; }
  std::size_t events() const { return events_.size(); }
  std::size_t dispatched() const { return next_; }
  const std::string& path() const { return path_; }
  // Empty, or where the log is damaged and the replay stops ("byte 123456 (after event 789,
  // t = 12.3 s): ...").
  const std::string& damage() const { return damage_; }

 private:
  struct Event {
    int64_t offset;  // of the event in the file
    double t;        // [s] replay time from the start
  };
  void DispatchUpTo(double t);

  std::string path_;
  std::function<GcsLink&()> reset_;
  GcsLink* link_;
  std::unique_ptr<lcm::LogFile> file_;
  std::vector<Event> events_;
  std::string damage_;
  double start_ = 0.0;      // [s] vehicle time of the log's first event
  double duration_ = 0.0;
  double position_ = 0.0;
  std::size_t next_ = 0;    // next event to dispatch
  bool paused_ = false;
  double speed_ = 1.0;
};

}  // namespace uav::gcs

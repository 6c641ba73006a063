#pragma once
// What the replay panel and scripts may do with a replayed log (the application implements it
// over LogReplay, which lives with the link; the model and the panels see only this).
#include <cstddef>
#include <string>

namespace uav::gcs {

class ReplayControl {
 public:
  virtual ~ReplayControl() = default;
  virtual void Seek(double t) = 0;  // [s] from the start of the log
  virtual void Pause() = 0;
  virtual void Play() = 0;
  virtual bool SetSpeed(double speed) = 0;  // false: outside the allowed range
  virtual double speed() const = 0;
  virtual double position() const = 0;  // [s] from the start
  virtual double duration() const = 0;  // [s]
  virtual bool paused() const = 0;
  virtual std::size_t dispatched() const = 0;  // events played so far
  virtual std::size_t events() const = 0;
  virtual std::string damage() const = 0;  // empty, or where the log is damaged
  virtual std::string path() const = 0;
};

}  // namespace uav::gcs

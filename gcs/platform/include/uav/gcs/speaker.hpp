#pragma once
// Says sentences aloud with a text-to-speech program (espeak-ng by default, Debian `espeak-ng`),
// one at a time on a thread of its own: the UI never waits for speech. While one is being said,
// at most kQueued wait; older ones are dropped (a stale warning is worse than none).
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

namespace uav::gcs {

class Speaker {
 public:
  static constexpr std::size_t kQueued = 3;
  // `program`: run as `program TEXT`, found on PATH.
  explicit Speaker(std::string program = "espeak-ng");
  ~Speaker();
  Speaker(const Speaker&) = delete;
  Speaker& operator=(const Speaker&) = delete;

  bool available() const { return available_; }  // the program was found on PATH
  const std::string& program() const { return program_; }
  void Say(const std::string& sentence);
  int spoken() const;  // finished utterances

 private:
  void Run();

  std::string program_;
  bool available_ = false;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::string> queue_;
  bool stop_ = false;
  int spoken_ = 0;
  std::thread thread_;
};

}  // namespace uav::gcs

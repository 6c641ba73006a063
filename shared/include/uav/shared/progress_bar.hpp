#pragma once
// The command-line tools' progress bar: one line on stderr, rewritten in place, so that stdout
// stays free for the tool's report.
#include <cstddef>
#include <string>

namespace uav {

class ProgressBar {
 public:
  // total 0: not known in advance (a video container that does not say); only the count shows.
  explicit ProgressBar(std::size_t total) : total_(total) {}
  // Shows `done` with an optional note (a file name, a state). Redraws at most every 1 % (every
  // 10 items without a total) to keep terminals and logs light.
  void Update(std::size_t done, const std::string& note = "");
  // Draws the final state and ends the line.
  void Finish(std::size_t done);

 private:
  void Draw(std::size_t done, const std::string& note);
  std::size_t total_;
  long last_step_ = -1;
};

}  // namespace uav

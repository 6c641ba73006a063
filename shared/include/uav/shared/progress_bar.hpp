#pragma once
// The command-line tools' progress bar on stderr, so that stdout stays free for the tool's
// report: on a terminal one line rewritten in place; into a log (a file, a pipe) a plain line now
// and then, never the redraws.
#include <cstddef>
#include <string>

namespace uav {

class ProgressBar {
 public:
  // total 0: not known in advance (a video container that does not say); only the count shows.
  explicit ProgressBar(std::size_t total);
  // Shows `done` with an optional note (a file name, a state): on a terminal at most every 1 %
  // (every 10 items without a total), into a log every 10 % (every 100 items).
  void Update(std::size_t done, const std::string& note = "");
  // Draws the final state and ends the line (into a log: unless the last line already said it).
  void Finish(std::size_t done);

 private:
  void Draw(std::size_t done, const std::string& note);
  std::size_t total_;
  bool terminal_;
  long last_step_ = -1;
  std::size_t last_drawn_ = static_cast<std::size_t>(-1);
};

}  // namespace uav

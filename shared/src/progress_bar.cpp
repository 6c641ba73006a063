#include "uav/shared/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace uav {

ProgressBar::ProgressBar(std::size_t total) : total_(total), terminal_(isatty(STDERR_FILENO) == 1) {}

void ProgressBar::Update(std::size_t done, const std::string& note) {
  // A terminal redraws in place every 1 %; a log (stderr a file or a pipe) gets a plain line
  // every 10 %, or every 100 items without a total, so it stays short and readable.
  const std::size_t percent = total_ > 0 ? 100 * std::min(done, total_) / total_ : 0;
  const long step = total_ > 0 ? static_cast<long>(terminal_ ? percent : percent / 10)
                               : static_cast<long>(done / (terminal_ ? 10 : 100));
  if (step == last_step_) return;
  last_step_ = step;
  Draw(done, note);
}

void ProgressBar::Finish(std::size_t done) {
  if (terminal_) {
    Draw(done, "");
    std::fprintf(stderr, "\n");
  } else if (!(last_drawn_ == done && done == total_)) {
    Draw(done, "done");
  }
}

void ProgressBar::Draw(std::size_t done, const std::string& note) {
  last_drawn_ = done;
  const char* start = terminal_ ? "\r" : "";
  const char* end = terminal_ ? "" : "\n";
  if (total_ == 0) {
    std::fprintf(stderr, "%s%zu %-40s%s", start, done, note.c_str(), end);
  } else if (!terminal_) {
    std::fprintf(stderr, "%zu/%zu (%zu %%)%s%s\n", done, total_, 100 * std::min(done, total_) / total_,
                 note.empty() ? "" : " ", note.c_str());
  } else {
    constexpr std::size_t kWidth = 30;
    const std::size_t filled = kWidth * std::min(done, total_) / total_;
    std::fprintf(stderr, "\r[%s%s] %zu/%zu %-40s", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, ' ').c_str(), done, total_, note.c_str());
  }
  std::fflush(stderr);
}

}  // namespace uav

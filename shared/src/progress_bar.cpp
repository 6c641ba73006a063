#include "uav/shared/progress_bar.hpp"

#include <algorithm>
#include <cstdio>

namespace uav {

void ProgressBar::Update(std::size_t done, const std::string& note) {
  const long step = total_ > 0 ? static_cast<long>(100 * std::min(done, total_) / total_) : static_cast<long>(done / 10);
  if (step == last_step_) return;
  last_step_ = step;
  Draw(done, note);
}

void ProgressBar::Finish(std::size_t done) {
  Draw(done, "");
  std::fprintf(stderr, "\n");
}

void ProgressBar::Draw(std::size_t done, const std::string& note) {
  if (total_ == 0) {
    std::fprintf(stderr, "\r%zu %-40s", done, note.c_str());
  } else {
    constexpr std::size_t kWidth = 30;
    const std::size_t filled = kWidth * std::min(done, total_) / total_;
    std::fprintf(stderr, "\r[%s%s] %zu/%zu %-40s", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, ' ').c_str(), done, total_, note.c_str());
  }
  std::fflush(stderr);
}

}  // namespace uav

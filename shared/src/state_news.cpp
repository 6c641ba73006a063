#include "uav/shared/state_news.hpp"

#include <algorithm>
#include <cstdio>

namespace uav {
namespace {

std::string Quoted(const std::string& s) { return s.empty() ? "(none)" : s; }

// "a, b and c"
std::string List(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) s += i + 1 == items.size() ? " and " : ", ";
    s += Quoted(items[i]);
  }
  return s;
}

}  // namespace

std::optional<std::string> StateNews::Update(const std::string& state, double t) {
  if (!started_ || state != current_) {
    const bool first = !started_;
    started_ = true;
    current_ = state;
    current_since_ = t;
    if (first || (!flapping_since_ && t - said_at_ >= settle_s_)) {
      const bool news = state != said_;
      said_ = state;
      if (!news || state.empty()) return std::nullopt;  // falling silent is not said
      said_at_ = t;
      return state;
    }
    // Too soon after the last change said: held back until something settles.
    if (!flapping_since_) {
      flapping_since_ = said_at_;
      flapped_ = {said_};
    }
    if (std::find(flapped_.begin(), flapped_.end(), state) == flapped_.end()) flapped_.push_back(state);
    return std::nullopt;
  }
  if (!flapping_since_ || t - current_since_ < settle_s_) return std::nullopt;
  // Settled after flapping: said once, with how long it went on and between what.
  char lasted[32];
  std::snprintf(lasted, sizeof lasted, "%.1f s", current_since_ - *flapping_since_);
  const std::string summary = "after " + std::string(lasted) + " of changes between " + List(flapped_);
  const bool back = state == said_;
  flapping_since_.reset();
  flapped_.clear();
  said_ = state, said_at_ = t;
  if (state.empty()) return std::string("settled ") + summary;
  return (back ? state + " again (" : state + " (") + summary + ")";
}

}  // namespace uav

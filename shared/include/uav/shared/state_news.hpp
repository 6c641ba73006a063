#pragma once
// What an operator is told of a state that changes: each change at once, unless it comes within
// `settle_s` of the last one said. Changes that come faster than that (a state flapping between
// "avoiding" and "no data" every 0.3 s) are held back and, once a state has held for settle_s,
// said once with how long the flapping lasted and what it flapped between. Nothing is lost:
// the state that settles is always said, and a flap that settles back where it began says so.
#include <optional>
#include <string>
#include <vector>

namespace uav {

class StateNews {
 public:
  explicit StateNews(double settle_s) : settle_s_(settle_s) {}
  // The state now (t: seconds on any clock that does not go back); the text to say, if any.
  // The first state seen is said (an empty state is never said: "nothing to report").
  std::optional<std::string> Update(const std::string& state, double t);
  // The state last said.
  const std::string& said() const { return said_; }

 private:
  double settle_s_;
  bool started_ = false;
  std::string current_, said_;
  double current_since_ = 0;
  double said_at_ = -1e300;  // when something was last said aloud
  std::optional<double> flapping_since_;
  std::vector<std::string> flapped_;  // the states seen while flapping, in order of first sight
};

}  // namespace uav

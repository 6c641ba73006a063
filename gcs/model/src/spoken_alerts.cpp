#include "uav/gcs/spoken_alerts.hpp"

namespace uav::gcs {

std::vector<std::string> SpokenAlerts::Take(const MessageLog& log, double now) {
  std::vector<std::string> out;
  const std::size_t fresh = log.added() - seen_;
  seen_ = log.added();
  const auto& lines = log.lines();
  const std::size_t first = lines.size() - std::min(fresh, lines.size());
  std::map<std::string, int> more;  // per vehicle, warnings not read out
  for (std::size_t i = first; i < lines.size(); ++i) {
    const LogLine& l = lines[i];
    if (l.severity > Severity::kWarning) continue;
    const std::string who = l.vehicle_id.empty() ? "ground station" : l.vehicle_id;
    const std::string sentence = who + ": " + l.text;
    const auto said = said_at_.find(sentence);
    if (said != said_at_.end() && now - said->second < kRepeatAfter) continue;
    said_at_[sentence] = now;
    if (static_cast<int>(out.size()) < kMaxPerTake) out.push_back(sentence);
    else ++more[who];
  }
  for (const auto& [who, n] : more) out.push_back(who + ": " + std::to_string(n) + " more warning" + (n > 1 ? "s" : ""));
  return out;
}

}  // namespace uav::gcs

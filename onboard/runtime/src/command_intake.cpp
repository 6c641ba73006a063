#include "uav/runtime/command_intake.hpp"

namespace uav::runtime {

CommandIntake::Result CommandIntake::Receive(const std::string& addressed_to,
                                             const std::string& source, int64_t command_seq,
                                             const std::string& text) {
  Result r;
  auto reject = [&](const std::string& command, const std::string& why) {
    CommandAck rep{source, command_seq, command, control::AckResult::kRejected, 0, why};
    Remember(rep);
    r.replies.push_back(rep);
  };
  if (addressed_to != vehicle_id_) return r;  // not ours: another vehicle on the same bus
  const auto key = std::make_pair(source, command_seq);
  if (auto it = seen_.find(key); it != seen_.end()) {
    r.replies.push_back(it->second);  // a resend: answer again, do not execute again
    return r;
  }
  if (source.empty()) return reject(text, "command has no source"), r;
  if (source == kVehicleInitiatedSource)  // its acknowledgements would read as the vehicle's own rows
    return reject(text, "a GCS may not be named '" + source + "': that is the vehicle's own name for what it does on its own"), r;
  const ParseResult parsed = ParseCommand(text);
  if (!parsed.ok()) return reject(text, parsed.error), r;
  // Mark as seen now so a resend arriving before the task manager answers is not run twice.
  seen_[key] = {source, command_seq, parsed.command->Name(), control::AckResult::kAccepted, 0, ""};
  r.request = control::CommandRequest{source, command_seq, *parsed.command};
  return r;
}

void CommandIntake::Remember(const CommandAck& report) {
  seen_[{report.source, report.command_seq}] = report;
  while (seen_.size() > kMaxRemembered) {
    // Drop the lowest sequence number (oldest) of any source.
    auto oldest = seen_.begin();
    for (auto it = seen_.begin(); it != seen_.end(); ++it)
      if (it->first.second < oldest->first.second) oldest = it;
    seen_.erase(oldest);
  }
}

}  // namespace uav::runtime

#include "uav/gcs/commands.hpp"

#include <algorithm>
#include <iterator>

#include "uav/shared/command_grammar.hpp"

namespace uav::gcs {

bool CommandCenter::Submit(const std::string& text, const std::string& vehicle_id, double now, MessageLog& log) {
  if (!refusal_.empty()) {
    error_ = refusal_;
    return false;
  }
  const ParseResult parsed = ParseCommand(text);
  if (!parsed.ok()) {
    error_ = parsed.error;
    return false;
  }
  return Queue(parsed.command->Text(), text, vehicle_id, now, log);
}

bool CommandCenter::SubmitForeignParameter(const std::string& name, const std::string& value,
                                           const std::string& vehicle_id, double now, MessageLog& log) {
  if (!refusal_.empty()) {
    error_ = refusal_;
    return false;
  }
  const std::string text = "param " + name + " " + value;
  return Queue(text, text, vehicle_id, now, log);
}

bool CommandCenter::Queue(const std::string& canonical, const std::string& text, const std::string& vehicle_id,
                          double now, MessageLog& log) {
  if (vehicle_id.empty()) {
    error_ = "no vehicle selected";
    return false;
  }
  error_.clear();
  if (history_.empty() || history_.back() != text) history_.push_back(text);
  SentCommand c;
  c.command_seq = next_seq_++;
  c.vehicle_id = vehicle_id;
  c.text = canonical;
  c.first_sent = c.last_sent = now;
  c.tries = 1;
  Keep(c);
  outgoing_.push_back({c.vehicle_id, c.command_seq, c.text});
  log.Add(now, vehicle_id, "sent: " + canonical, Severity::kInfo);
  return true;
}

std::optional<Eigen::Vector3d> CommandCenter::ActiveGoto(const std::string& vehicle_id) const {
  for (auto it = sent_.rbegin(); it != sent_.rend(); ++it) {
    if (it->vehicle_id != vehicle_id || it->vehicle_initiated) continue;
    const ParseResult parsed = ParseCommand(it->text);
    if (!parsed.ok() || parsed.command->id != CommandId::kGoto) continue;
    // A task that ends, or another that supersedes it (a hover, a failsafe), sends its owner the
    // final result: only the newest goto counts, and only while it runs.
    if (!it->last_ack) return std::nullopt;
    const CommandResult r = it->last_ack->result;
    if (r != CommandResult::kAccepted && r != CommandResult::kInProgress) return std::nullopt;
    const std::vector<double>& a = parsed.command->args;
    return Eigen::Vector3d(a[0], a[1], -a[2]);
  }
  return std::nullopt;
}

void CommandCenter::Keep(SentCommand c) {
  sent_.push_back(std::move(c));
  while (sent_.size() > kMaxSentKept) sent_.pop_front();
}

void CommandCenter::OnAck(const std::string& vehicle_id, const CommandAck& ack, double now,
                          MessageLog& log) {
  if (ack.source == kVehicleInitiatedSource) return OnVehicleReport(vehicle_id, ack, now, log);
  if (ack.source != gcs_name_) return;  // another GCS's conversation
  for (auto& c : sent_) {
    if (c.vehicle_initiated || c.command_seq != ack.command_seq || c.vehicle_id != vehicle_id) continue;
    c.acknowledged = true;
    const bool changed = !c.last_ack || c.last_ack->result != ack.result;
    c.last_ack = ack;
    if (changed && ack.result != CommandResult::kInProgress) {
      log.Add(now, vehicle_id,
              c.text + ": " + std::string(Name(ack.result)) + (ack.reason.empty() ? "" : " (" + ack.reason + ")"),
              IsFailure(ack.result) ? Severity::kWarning : Severity::kInfo);
    }
  }
}

void CommandCenter::OnVehicleReport(const std::string& vehicle_id, const CommandAck& ack, double now, MessageLog& log) {
  auto row = std::find_if(sent_.begin(), sent_.end(), [&](const SentCommand& c) {
    return c.vehicle_initiated && c.vehicle_id == vehicle_id && c.command_seq == ack.command_seq;
  });
  if (row == sent_.end()) {
    SentCommand c;
    c.command_seq = ack.command_seq;
    c.vehicle_id = vehicle_id;
    c.text = ack.command;
    c.first_sent = c.last_sent = now;
    c.acknowledged = true;
    c.vehicle_initiated = true;
    Keep(std::move(c));
    row = std::prev(sent_.end());
  }
  const bool changed = !row->last_ack || row->last_ack->result != ack.result;
  row->last_ack = ack;
  if (!changed || ack.result == CommandResult::kInProgress) return;
  // The vehicle taking over is a warning the operator must see; its end is news.
  const bool warn = ack.result == CommandResult::kAccepted || IsFailure(ack.result);
  log.Add(now, vehicle_id,
          "vehicle: " + row->text + " " + std::string(Name(ack.result)) + (ack.reason.empty() ? "" : " (" + ack.reason + ")"),
          warn ? Severity::kWarning : Severity::kInfo);
}

void CommandCenter::Tick(double now, MessageLog& log) {
  for (auto& c : sent_) {
    if (c.acknowledged || c.gave_up || now - c.last_sent < kResendTimeout) continue;
    if (c.tries >= kMaxTries) {
      c.gave_up = true;
      log.Add(now, c.vehicle_id, c.text + ": no acknowledgement after " + std::to_string(kMaxTries) + " tries",
              Severity::kError);
      continue;
    }
    ++c.tries;
    c.last_sent = now;
    outgoing_.push_back({c.vehicle_id, c.command_seq, c.text});  // same command_seq
  }
}

}  // namespace uav::gcs

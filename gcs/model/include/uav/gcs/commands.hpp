#pragma once
// Commands to the vehicles: checked with the shared grammar, sent with a sequence number,
// resent until acknowledged (the same number: the vehicle treats a repeat as the same request),
// and given up after kMaxTries.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "uav/gcs/message_log.hpp"
#include "uav/shared/operator_messages.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::gcs {

struct SentCommand {
  int64_t command_seq = 0;
  std::string vehicle_id;
  std::string text;
  double first_sent = 0.0;  // [s] GCS clock
  double last_sent = 0.0;
  int tries = 0;
  bool acknowledged = false;
  bool gave_up = false;
  // What the vehicle did on its own (a failsafe): a row of its own, numbered by the vehicle.
  bool vehicle_initiated = false;
  std::optional<CommandAck> last_ack;
};

// An outgoing message the link must send.
struct OutgoingCommand {
  std::string vehicle_id;
  int64_t command_seq;
  std::string text;
};

class CommandCenter {
 public:
  static constexpr double kResendTimeout = 1.0;  // [s] without any acknowledgement
  static constexpr int kMaxTries = 5;
  static constexpr std::size_t kMaxSentKept = 100;

  // Commands are identified by (gcs_name, command_seq) on the vehicle, so a restarted GCS must
  // not reuse numbers: `first_seq` grows across runs (wall-clock microseconds).
  CommandCenter(std::string gcs_name, int64_t first_seq) : gcs_name_(std::move(gcs_name)), next_seq_(first_seq) {}

  // Queues `text` for `vehicle_id`. Returns false and sets error() when the text is invalid, no
  // vehicle is selected (empty id), or sending is off (replay: `refusal` says why).
  bool Submit(const std::string& text, const std::string& vehicle_id, double now, MessageLog& log);
  // `param NAME VALUE` to a vehicle whose parameters are not ours (a MAVLink autopilot's): the
  // name and value were checked against the vehicle's own table, not our grammar.
  bool SubmitForeignParameter(const std::string& name, const std::string& value, const std::string& vehicle_id,
                              double now, MessageLog& log);
  // Only answers to this GCS count, and the vehicle's reports of what it does on its own (source
  // kVehicleInitiatedSource), which get rows of their own; a changed result is logged.
  void OnAck(const std::string& vehicle_id, const CommandAck& ack, double now, MessageLog& log);
  void Tick(double now, MessageLog& log);
  std::vector<OutgoingCommand> TakeOutgoing() { return std::exchange(outgoing_, {}); }
  // Sending off (with the reason the command bar shows) or on (empty).
  void SetRefusal(std::string why) { refusal_ = std::move(why); }
  int64_t NextSeq() { return next_seq_++; }  // shared with mission uploads: one number space

  const std::string& gcs_name() const { return gcs_name_; }
  const std::string& error() const { return error_; }
  const std::string& refusal() const { return refusal_; }
  const std::vector<std::string>& history() const { return history_; }
  const std::deque<SentCommand>& sent() const { return sent_; }
  // Where this GCS's newest goto to `vehicle_id` goes (north, east, down [m] in the vehicle's N),
  // while the vehicle flies it: accepted and not yet completed, replaced or refused.
  std::optional<Eigen::Vector3d> ActiveGoto(const std::string& vehicle_id) const;

 private:
  std::string gcs_name_;
  int64_t next_seq_;
  std::string error_;
  std::string refusal_;
  std::vector<std::string> history_;
  std::deque<SentCommand> sent_;
  std::vector<OutgoingCommand> outgoing_;

  bool Queue(const std::string& text, const std::string& typed, const std::string& vehicle_id, double now, MessageLog& log);
  void OnVehicleReport(const std::string& vehicle_id, const CommandAck& ack, double now, MessageLog& log);
  void Keep(SentCommand c);
};

}  // namespace uav::gcs

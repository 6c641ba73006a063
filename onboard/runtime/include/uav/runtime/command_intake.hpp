#pragma once
// Where commands enter the vehicle (thesis 2.3.2: "first it is validated, and then extracted"):
// checks the addressing, parses with the shared grammar, and recognises resends.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uav/control/task_manager.hpp"

namespace uav::runtime {

class CommandIntake {
 public:
  explicit CommandIntake(std::string vehicle_id) : vehicle_id_(std::move(vehicle_id)) {}

  struct Result {
    std::optional<control::CommandRequest> request;  // to the task manager
    std::vector<CommandAck> replies;        // to send back now
  };
  Result Receive(const std::string& addressed_to, const std::string& source, int64_t command_seq,
                 const std::string& text);

  // Every report sent for a command is remembered so that a resend of it is answered with the
  // latest state instead of being executed again.
  void Remember(const CommandAck& report);

 private:
  std::string vehicle_id_;
  // (source, command_seq) -> latest report. Bounded: the oldest sequence numbers are dropped.
  std::map<std::pair<std::string, int64_t>, CommandAck> seen_;
  static constexpr std::size_t kMaxRemembered = 256;
};

}  // namespace uav::runtime

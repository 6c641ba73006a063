#include "uav/shared/channels.hpp"

#include <cctype>

namespace uav {

std::string Channel(std::string_view vehicle_id, Topic t) {
  return std::string(vehicle_id) + "/" + TopicName(t);
}

bool IsValidVehicleId(std::string_view id) {
  if (id.empty() || id.size() > 32) return false;
  for (char c : id)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

}  // namespace uav

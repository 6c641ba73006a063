#include "uav/shared/mavlink_autopilots.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace uav::mavlink {
namespace {

constexpr uint32_t Px4(uint8_t main, uint8_t sub = 0) { return (uint32_t{main} << 16) | (uint32_t{sub} << 24); }

bool SameName(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

}  // namespace

std::string_view Name(Autopilot a) {
  switch (a) {
    case Autopilot::kPx4: return "PX4";
    case Autopilot::kArduCopter: return "ArduCopter";
    case Autopilot::kArduPlane: return "ArduPlane";
    case Autopilot::kArduPlaneVtol: return "ArduPlane VTOL";
    case Autopilot::kOther: break;
  }
  return "generic";
}

bool IsArduPilot(Autopilot a) {
  return a == Autopilot::kArduCopter || a == Autopilot::kArduPlane || a == Autopilot::kArduPlaneVtol;
}

bool IsVtolType(uint8_t t) { return t >= 19 && t <= 25; }
bool IsFixedWingType(uint8_t t) { return t == 1 || t == 16 || t == 28; }

Autopilot RecognizeAutopilot(uint8_t autopilot, uint8_t type) {
  if (autopilot == kAutopilotPx4) return Autopilot::kPx4;
  if (autopilot != kAutopilotArduPilot) return Autopilot::kOther;
  if (IsVtolType(type)) return Autopilot::kArduPlaneVtol;
  if (IsFixedWingType(type)) return Autopilot::kArduPlane;
  return Autopilot::kArduCopter;  // quad, hexa, octo, tri, coaxial, heli, dodeca, deca
}

std::string_view VehicleTypeName(uint8_t t) {
  switch (t) {
    case 1: return "fixed wing";
    case 2: return "quadrotor";
    case 3: return "coaxial";
    case 4: return "helicopter";
    case 13: return "hexarotor";
    case 14: return "octorotor";
    case 15: return "tricopter";
    case 19: return "VTOL tail-sitter (duo)";
    case 20: return "VTOL tail-sitter (quad)";
    case 21: return "VTOL tilt-rotor";
    case 22: return "VTOL fixed-rotor";
    case 23: return "VTOL tail-sitter";
    case 24: return "VTOL tilt-wing";
    case 29: return "dodecarotor";
    case 35: return "decarotor";
    default: return "other";
  }
}

const std::vector<AutopilotMode>& ModesOf(Autopilot a) {
  // PX4: px4_custom_mode.h (main modes 1-8; AUTO's sub-modes 1-9).
  static const std::vector<AutopilotMode> kPx4 = {
      {Px4(1), "Manual", Task::kSticks},          {Px4(2), "Altitude", Task::kSticks},
      {Px4(3), "Position", Task::kSticks},        {Px4(4, 1), "Ready", Task::kIdle},
      {Px4(4, 2), "Takeoff", Task::kTakeoff},     {Px4(4, 3), "Hold", Task::kHover},
      {Px4(4, 4), "Mission", Task::kMission},     {Px4(4, 5), "Return", Task::kReturn},
      {Px4(4, 6), "Land", Task::kLand},           {Px4(4, 8), "Follow Me", Task::kFollow},
      {Px4(4, 9), "Precision Land", Task::kLand}, {Px4(5), "Acro", Task::kSticks},
      {Px4(6), "Offboard", std::nullopt},         {Px4(7), "Stabilized", Task::kSticks},
  };
  // ArduCopter: ArduCopter/mode.h, enum class Number.
  static const std::vector<AutopilotMode> kCopter = {
      {0, "Stabilize", Task::kSticks}, {1, "Acro", Task::kSticks},      {2, "AltHold", Task::kSticks},
      {3, "Auto", Task::kMission},     {4, "Guided", Task::kGoto},      {5, "Loiter", Task::kHover},
      {6, "RTL", Task::kReturn},       {7, "Circle", std::nullopt},     {9, "Land", Task::kLand},
      {11, "Drift", Task::kSticks},    {13, "Sport", Task::kSticks},    {16, "PosHold", Task::kSticks},
      {17, "Brake", Task::kHover},     {21, "Smart RTL", Task::kReturn}, {23, "Follow", Task::kFollow},
      {27, "Auto RTL", Task::kReturn},
  };
  // ArduPlane: ArduPlane/mode.h, enum class Number (the Q modes are a QuadPlane's).
  static const std::vector<AutopilotMode> kPlane = {
      {0, "Manual", Task::kSticks},   {1, "Circle", Task::kHover},    {2, "Stabilize", Task::kSticks},
      {3, "Training", Task::kSticks}, {4, "Acro", Task::kSticks},     {5, "FBWA", Task::kSticks},
      {6, "FBWB", Task::kSticks},     {7, "Cruise", Task::kSticks},   {8, "Autotune", std::nullopt},
      {10, "Auto", Task::kMission},   {11, "RTL", Task::kReturn},     {12, "Loiter", Task::kHover},
      {13, "Takeoff", Task::kTakeoff}, {15, "Guided", Task::kGoto},   {17, "QStabilize", Task::kSticks},
      {18, "QHover", Task::kSticks},  {19, "QLoiter", Task::kHover},  {20, "QLand", Task::kLand},
      {21, "QRTL", Task::kReturn},
  };
  static const std::vector<AutopilotMode> kNone;
  switch (a) {
    case Autopilot::kPx4: return kPx4;
    case Autopilot::kArduCopter: return kCopter;
    case Autopilot::kArduPlane:
    case Autopilot::kArduPlaneVtol: return kPlane;
    case Autopilot::kOther: break;
  }
  return kNone;
}

const AutopilotMode* FindMode(Autopilot a, uint32_t custom_mode) {
  for (const AutopilotMode& m : ModesOf(a)) {
    // PX4 reports a sub-mode only in AUTO: elsewhere bits 24-31 carry nothing.
    const bool px4_plain = a == Autopilot::kPx4 && ((m.custom_mode >> 16) & 0xFF) != 4;
    if (px4_plain ? (m.custom_mode & 0x00FF0000u) == (custom_mode & 0x00FF0000u) : m.custom_mode == custom_mode) return &m;
  }
  return nullptr;
}

const AutopilotMode* FindModeNamed(Autopilot a, std::string_view name) {
  for (const AutopilotMode& m : ModesOf(a))
    if (SameName(m.name, name)) return &m;
  return nullptr;
}

std::string ModeName(Autopilot a, uint32_t custom_mode) {
  if (const AutopilotMode* m = FindMode(a, custom_mode)) return m->name;
  char text[32];
  std::snprintf(text, sizeof text, a == Autopilot::kPx4 ? "mode 0x%08x" : "mode %u", custom_mode);
  return text;
}

ParamEncoding ParamEncodingOf(Autopilot a) { return a == Autopilot::kPx4 ? ParamEncoding::kBytewise : ParamEncoding::kCCast; }

namespace {
struct IntRange {
  double lo, hi;
};
std::optional<IntRange> RangeOf(uint8_t type) {
  switch (type) {
    case 1: return IntRange{0, 255};
    case 2: return IntRange{-128, 127};
    case 3: return IntRange{0, 65535};
    case 4: return IntRange{-32768, 32767};
    case 5: return IntRange{0, 4294967295.0};
    case 6: return IntRange{-2147483648.0, 2147483647.0};
    default: return std::nullopt;
  }
}
}  // namespace

std::optional<double> DecodeParamValue(float wire, uint8_t type, ParamEncoding e) {
  if (type == kParamReal32) return wire;
  if (!RangeOf(type)) return std::nullopt;
  if (e == ParamEncoding::kCCast) return wire;
  uint32_t bits = 0;
  std::memcpy(&bits, &wire, sizeof bits);
  switch (type) {
    case 1: return static_cast<double>(static_cast<uint8_t>(bits));
    case 2: return static_cast<double>(static_cast<int8_t>(bits));
    case 3: return static_cast<double>(static_cast<uint16_t>(bits));
    case 4: return static_cast<double>(static_cast<int16_t>(bits));
    case 5: return static_cast<double>(bits);
    default: return static_cast<double>(static_cast<int32_t>(bits));
  }
}

std::optional<float> EncodeParamValue(double value, uint8_t type, ParamEncoding e, std::string* why) {
  if (!std::isfinite(value)) {
    *why = "the value is not finite";
    return std::nullopt;
  }
  if (type == kParamReal32) return static_cast<float>(value);
  const std::optional<IntRange> range = RangeOf(type);
  if (!range) {
    *why = "parameter type " + std::to_string(type) + " does not fit a PARAM_SET (64-bit or unknown)";
    return std::nullopt;
  }
  if (value != std::floor(value) || value < range->lo || value > range->hi) {
    char text[96];
    std::snprintf(text, sizeof text, "an integer parameter takes whole numbers from %.0f to %.0f", range->lo, range->hi);
    *why = text;
    return std::nullopt;
  }
  if (e == ParamEncoding::kCCast) return static_cast<float>(value);
  // Byte-wise: the integer's bytes, little-endian in the low bytes, the rest zero.
  uint32_t bits = 0;
  if (type == 2) bits = static_cast<uint8_t>(static_cast<int8_t>(value));
  else if (type == 4) bits = static_cast<uint16_t>(static_cast<int16_t>(value));
  else if (type == 6) bits = static_cast<uint32_t>(static_cast<int32_t>(value));
  else bits = static_cast<uint32_t>(value);
  float wire = 0.f;
  std::memcpy(&wire, &bits, sizeof wire);
  return wire;
}

bool HomeIsMissionItemZero(Autopilot a) { return IsArduPilot(a); }

}  // namespace uav::mavlink

#pragma once
namespace uav::gcs {
// The built-in demo (`uav-gcs --demo`): take off, hover, go to a point, land, checking each
// target from telemetry.
extern const char* const kDemoScript;
}  // namespace uav::gcs

#pragma once
namespace uav::gcs {
// The built-in demo (`uav-gcs --demo`): the main job's survey over the village, every step
// checked from what the GCS receives.
extern const char* const kDemoScript;
// The same survey flown by U-Lion (`uav-gcs --demo-ulion`): planned for its cruise and turns,
// taken off vertically, surveyed on the wing, landed vertically at home.
extern const char* const kDemoScriptULion;
}  // namespace uav::gcs

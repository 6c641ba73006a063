#pragma once
// Delivers a script's typing and clicks to the panels as real ImGui input (mouse moves, button
// presses, characters, Enter), so a headless run exercises exactly the code a person drives.
#include <deque>
#include <functional>
#include <string>

#include "uav/gcs/script.hpp"
#include "uav/gcs/ui_context.hpp"

namespace uav::gcs {

class ImGuiScriptDriver : public ScriptDriver {
 public:
  using ScreenshotFn = std::function<int(const std::string& path, std::string* error)>;
  ImGuiScriptDriver(const UiContext& ctx, ScreenshotFn screenshot)
      : ctx_(ctx), screenshot_(std::move(screenshot)) {}

  bool StartType(const std::string& text, std::string* error) override;
  bool StartClick(const std::string& label, std::string* error) override;
  bool StartSet(const std::string& label, const std::string& text, std::string* error) override;
  bool StartMapClick(double north, double east, bool right, std::string* error) override;
  bool StartMapDrag(double n1, double e1, double n2, double e2, std::string* error) override;
  bool StartMapZoom(double north, double east, int steps, std::string* error) override;
  bool StartGesture(const std::string& label, Gesture g, double fx1, double fy1, double fx2, double fy2, int steps,
                    std::string* error) override;
  bool StartKey(const std::string& key, bool ctrl, std::string* error) override;
  bool InputPending() const override { return !events_.empty(); }
  int Screenshot(const std::string& path, std::string* error) override;

  // Applies the next queued event; call after the platform's new-frame and before
  // ImGui::NewFrame.
  void ApplyNextEvent();

 private:
  struct Event {
    enum Kind { kMove, kDown, kUp, kRightDown, kRightUp, kSelectAllDown, kSelectAllUp, kText, kEnterDown, kEnterUp, kWheel,
                kKeyDown, kKeyUp } kind;
    float x = 0, y = 0;
    std::string text;
    int key = -1;
    bool ctrl = false;
  };
  bool QueueClick(const std::string& label, std::string* error);
  const WidgetRect* Usable(const std::string& label, std::string* error) const;
  bool QueueTyping(const std::string& label, const std::string& text, std::string* error);
  // Screen position of a map point; false (and *error) when the map is not on screen.
  bool MapToScreen(double north, double east, float* x, float* y, std::string* error) const;

  const UiContext& ctx_;
  ScreenshotFn screenshot_;
  std::deque<Event> events_;
  float mouse_x_ = -1, mouse_y_ = -1;
  bool mouse_down_ = false;
  bool right_down_ = false;
};

}  // namespace uav::gcs

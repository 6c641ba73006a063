#include "uav/gcs/script_input.hpp"

#include <cctype>
#include <cstdlib>
#include <utility>

#include <imgui.h>

namespace uav::gcs {

const WidgetRect* ImGuiScriptDriver::Usable(const std::string& label, std::string* error) const {
  auto it = ctx_.widgets.find(label);
  if (it == ctx_.widgets.end()) {
    *error = "no widget '" + label + "' on screen";
    return nullptr;
  }
  if (!it->second.disabled.empty()) {  // a person's click would do nothing: say so, fail the step
    *error = "'" + label + "' is disabled: " + it->second.disabled;
    return nullptr;
  }
  return &it->second;
}

bool ImGuiScriptDriver::QueueClick(const std::string& label, std::string* error) {
  const WidgetRect* w = Usable(label, error);
  if (!w) return false;
  const float x = 0.5f * (w->x0 + w->x1), y = 0.5f * (w->y0 + w->y1);
  events_.push_back({Event::kMove, x, y, {}});
  events_.push_back({Event::kDown, x, y, {}});
  events_.push_back({Event::kUp, x, y, {}});
  return true;
}

bool ImGuiScriptDriver::StartClick(const std::string& label, std::string* error) {
  return QueueClick(label, error);
}

bool ImGuiScriptDriver::StartType(const std::string& text, std::string* error) {
  return QueueTyping("command", text, error);  // focus the command bar as a person would
}

bool ImGuiScriptDriver::StartSet(const std::string& label, const std::string& text, std::string* error) {
  return QueueTyping(label, text, error);
}

bool ImGuiScriptDriver::MapToScreen(double north, double east, float* x, float* y, std::string* error) const {
  const MapTransform& m = ctx_.map;
  if (!m.valid) {
    *error = "the map is not on screen";
    return false;
  }
  *x = m.screen_cx + static_cast<float>((east - m.center_e) * m.px_per_m);
  *y = m.screen_cy - static_cast<float>((north - m.center_n) * m.px_per_m);
  const auto it = ctx_.widgets.find("map");
  if (it == ctx_.widgets.end() || *x < it->second.x0 || *x > it->second.x1 || *y < it->second.y0 || *y > it->second.y1) {
    *error = "map point N " + std::to_string(north) + " E " + std::to_string(east) + " is outside the visible map";
    return false;
  }
  return true;
}

bool ImGuiScriptDriver::StartMapClick(double north, double east, bool right, std::string* error) {
  float x, y;
  if (!MapToScreen(north, east, &x, &y, error)) return false;
  events_.push_back({Event::kMove, x, y, {}});
  events_.push_back({right ? Event::kRightDown : Event::kDown, x, y, {}});
  events_.push_back({right ? Event::kRightUp : Event::kUp, x, y, {}});
  return true;
}

bool ImGuiScriptDriver::StartMapDrag(double n1, double e1, double n2, double e2, std::string* error) {
  float x1, y1, x2, y2;
  if (!MapToScreen(n1, e1, &x1, &y1, error) || !MapToScreen(n2, e2, &x2, &y2, error)) return false;
  events_.push_back({Event::kMove, x1, y1, {}});
  events_.push_back({Event::kDown, x1, y1, {}});
  for (int i = 1; i <= 8; ++i)  // a hand moves over several frames
    events_.push_back({Event::kMove, x1 + (x2 - x1) * i / 8.0f, y1 + (y2 - y1) * i / 8.0f, {}});
  events_.push_back({Event::kUp, x2, y2, {}});
  return true;
}

bool ImGuiScriptDriver::StartMapZoom(double north, double east, int steps, std::string* error) {
  float x, y;
  if (!MapToScreen(north, east, &x, &y, error)) return false;
  events_.push_back({Event::kMove, x, y, {}});
  for (int i = 0; i < std::abs(steps); ++i) events_.push_back({Event::kWheel, steps > 0 ? 1.0f : -1.0f, 0, {}});
  return true;
}

bool ImGuiScriptDriver::StartGesture(const std::string& label, Gesture g, double fx1, double fy1, double fx2,
                                     double fy2, int steps, std::string* error) {
  const WidgetRect* w = Usable(label, error);
  if (!w) return false;
  const WidgetRect& r = *w;
  auto at = [&](double fx, double fy) {
    return std::pair<float, float>(r.x0 + static_cast<float>(fx) * (r.x1 - r.x0 - 1),
                                   r.y0 + static_cast<float>(fy) * (r.y1 - r.y0 - 1));
  };
  const auto [x1, y1] = at(fx1, fy1);
  events_.push_back({Event::kMove, x1, y1, {}});
  switch (g) {
    case Gesture::kClick:
      events_.push_back({Event::kDown, x1, y1, {}});
      events_.push_back({Event::kUp, x1, y1, {}});
      break;
    case Gesture::kRightClick:
      events_.push_back({Event::kRightDown, x1, y1, {}});
      events_.push_back({Event::kRightUp, x1, y1, {}});
      break;
    case Gesture::kDrag: {
      const auto [x2, y2] = at(fx2, fy2);
      events_.push_back({Event::kDown, x1, y1, {}});
      for (int i = 1; i <= 8; ++i)  // a hand moves over several frames
        events_.push_back({Event::kMove, x1 + (x2 - x1) * i / 8.0f, y1 + (y2 - y1) * i / 8.0f, {}});
      events_.push_back({Event::kUp, x2, y2, {}});
      break;
    }
    case Gesture::kWheel:
      for (int i = 0; i < std::abs(steps); ++i) events_.push_back({Event::kWheel, steps > 0 ? 1.0f : -1.0f, 0, {}});
      break;
    case Gesture::kHover:
      events_.push_back({Event::kMove, x1, y1, {}});  // and stay there
      break;
  }
  return true;
}

bool ImGuiScriptDriver::StartKey(const std::string& key, bool ctrl, std::string* error) {
  int index = -1;
  if (key == "escape") index = ImGui::GetIO().KeyMap[ImGuiKey_Escape];
  else if (key.size() == 1 && std::isalpha(static_cast<unsigned char>(key[0])))
    index = std::toupper(static_cast<unsigned char>(key[0]));  // GLFW's key codes for letters
  if (index < 0) {
    *error = "unknown key '" + key + "' (a letter or escape)";
    return false;
  }
  Event down{Event::kKeyDown, 0, 0, {}};
  down.key = index;
  down.ctrl = ctrl;
  Event up = down;
  up.kind = Event::kKeyUp;
  events_.push_back(down);
  events_.push_back(up);
  return true;
}

bool ImGuiScriptDriver::QueueTyping(const std::string& label, const std::string& text, std::string* error) {
  if (!QueueClick(label, error)) return false;
  // Replace whatever is in the bar (a rejected line stays there for editing): Ctrl+A, type.
  events_.push_back({Event::kSelectAllDown, 0, 0, {}});
  events_.push_back({Event::kSelectAllUp, 0, 0, {}});
  events_.push_back({Event::kText, 0, 0, text});
  events_.push_back({Event::kEnterDown, 0, 0, {}});
  events_.push_back({Event::kEnterUp, 0, 0, {}});
  return true;
}

int ImGuiScriptDriver::Screenshot(const std::string& path, std::string* error) {
  if (!screenshot_) {
    *error = "screenshots need the window (not available headless)";
    return -1;
  }
  return screenshot_(path, error);
}

void ImGuiScriptDriver::ApplyNextEvent() {
  ImGuiIO& io = ImGui::GetIO();
  const int enter = io.KeyMap[ImGuiKey_Enter];
  if (!events_.empty()) {
    const Event e = events_.front();
    events_.pop_front();
    switch (e.kind) {
      case Event::kMove: mouse_x_ = e.x, mouse_y_ = e.y; break;
      case Event::kDown: mouse_down_ = true; break;
      case Event::kUp: mouse_down_ = false; break;
      case Event::kRightDown: right_down_ = true; break;
      case Event::kRightUp: right_down_ = false; break;
      case Event::kSelectAllDown:
      case Event::kSelectAllUp: {
        const bool down = e.kind == Event::kSelectAllDown;
        io.KeyCtrl = down;
        if (io.KeyMap[ImGuiKey_A] >= 0) io.KeysDown[io.KeyMap[ImGuiKey_A]] = down;
        break;
      }
      case Event::kText:
        for (char c : e.text) io.AddInputCharacter(static_cast<unsigned char>(c));
        break;
      case Event::kEnterDown: if (enter >= 0) io.KeysDown[enter] = true; break;
      case Event::kEnterUp: if (enter >= 0) io.KeysDown[enter] = false; break;
      case Event::kWheel: io.MouseWheel += e.x; break;
      case Event::kKeyDown:
      case Event::kKeyUp: {
        const bool down = e.kind == Event::kKeyDown;
        io.KeyCtrl = down && e.ctrl;
        if (e.key >= 0 && e.key < IM_ARRAYSIZE(io.KeysDown)) io.KeysDown[e.key] = down;
        break;
      }
    }
  }
  // Hold the scripted pointer state every frame (a window backend would overwrite it).
  if (mouse_x_ >= 0) {
    io.MousePos = ImVec2(mouse_x_, mouse_y_);
    io.MouseDown[0] = mouse_down_;
    io.MouseDown[1] = right_down_;
  }
}

}  // namespace uav::gcs

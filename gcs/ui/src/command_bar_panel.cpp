// The command bar (thesis Fig. 2.8 bottom): typed commands checked as you type with the same
// grammar the vehicle uses, history (up/down), completion (tab), frequent actions as buttons
// that ask for confirmation, and the acknowledgement of the last command.
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"
#include "uav/shared/command_grammar.hpp"

namespace uav::gcs {
namespace {

struct CallbackData {
  GcsModel* model;
  UiState* state;
};

int OnInputEvent(ImGuiInputTextCallbackData* data) {
  auto* cb = static_cast<CallbackData*>(data->UserData);
  const auto& history = cb->model->commands().history();
  if (data->EventFlag == ImGuiInputTextFlags_CallbackCompletion) {
    const auto names = CompleteCommandName(std::string(data->Buf, data->BufTextLen));
    if (names.size() == 1) {
      data->DeleteChars(0, data->BufTextLen);
      data->InsertChars(0, (names[0] + " ").c_str());
    }
  } else if (data->EventFlag == ImGuiInputTextFlags_CallbackHistory && !history.empty()) {
    int& pos = cb->state->history_pos;
    const int n = static_cast<int>(history.size());
    if (data->EventKey == ImGuiKey_UpArrow) pos = pos < 0 ? n - 1 : std::max(0, pos - 1);
    else if (data->EventKey == ImGuiKey_DownArrow && pos >= 0) pos = pos + 1 >= n ? -1 : pos + 1;
    data->DeleteChars(0, data->BufTextLen);
    if (pos >= 0) data->InsertChars(0, history[pos].c_str());
  }
  return 0;
}

// Emergency stop (QGroundControl's): a red button, off while the vehicle is disarmed; it asks
// twice, in red, before `emergency_stop` goes out. Typing the command asks the same way.
void DrawEmergencyStop(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  const VehicleModel* v = model.selected();
  const bool disarmed = !v || !v->armed;
  if (disarmed) st.emergency_stop_asked = 0;
  BeginDisabledBecause(ctx, disarmed || model.replay(), model.replay() ? model.commands().refusal() : "disarmed: the motors are off");
  const ImVec4 red(0.75f, 0.1f, 0.1f, 1), bright(1, 0.3f, 0.3f, 1);
  ImGui::PushStyleColor(ImGuiCol_Button, red);
  if (ImGui::Button("EMERGENCY STOP")) st.emergency_stop_asked = 1;
  RegisterLastItem(ctx, "button:emergency_stop");
  if (st.emergency_stop_asked == 1) {
    ImGui::SameLine();
    ImGui::TextColored(bright, "stop the motors of %s now? It falls.", model.selected_id().c_str());
    ImGui::SameLine();
    if (ImGui::Button("Yes, stop the motors")) st.emergency_stop_asked = 2;
    RegisterLastItem(ctx, "emergency_stop:confirm");
  } else if (st.emergency_stop_asked == 2) {
    ImGui::SameLine();
    ImGui::TextColored(bright, "really? %s will fall from %.0f m.", model.selected_id().c_str(),
                       v && v->state ? v->state->altitude() : 0.0);
    ImGui::SameLine();
    if (ImGui::Button("STOP MOTORS NOW")) {
      model.SubmitCommand("emergency_stop", ctx.now);
      st.emergency_stop_asked = 0;
    }
    RegisterLastItem(ctx, "emergency_stop:confirm_again");
  }
  ImGui::PopStyleColor();
  if (st.emergency_stop_asked > 0) {
    ImGui::SameLine();
    if (ImGui::Button("Cancel##emergency")) st.emergency_stop_asked = 0;
    RegisterLastItem(ctx, "emergency_stop:cancel");
  }
  EndDisabledBecause(ctx);
}

}  // namespace

void DrawCommandBarPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Command");
  UiState& st = ctx.state;
  CallbackData cb{&model, &st};
  if (st.focus_command_bar) {
    ImGui::SetKeyboardFocusHere();
    st.focus_command_bar = false;
  }
  // A replay only watches: the bar and the buttons are off, and say why.
  BeginDisabledBecause(ctx, model.replay(), model.commands().refusal());
  ImGui::SetNextItemWidth(-1);
  const bool entered = ImGui::InputTextWithHint(
      "##command", "command, e.g. takeoff 10  (tab completes, up/down recalls)", &st.command_text,
      ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_CallbackCompletion |
          ImGuiInputTextFlags_CallbackHistory,
      OnInputEvent, &cb);
  RegisterLastItem(ctx, "command");
  if (entered && !model.replay()) {
    // A typed emergency stop asks twice, as the button does (disarmed, it goes: the vehicle says so).
    const ParseResult typed = ParseCommand(st.command_text);
    const bool ask = typed.ok() && typed.command->id == CommandId::kEmergencyStop && model.selected() && model.selected()->armed;
    if (ask) {
      st.emergency_stop_asked = 1;
      st.command_text.clear();
    } else if (model.SubmitCommand(st.command_text, ctx.now)) {
      st.command_text.clear();
    }
    st.history_pos = -1;
    st.focus_command_bar = true;  // keep typing
  }
  // Live validation with the vehicle's own grammar.
  if (model.replay()) {
    ImGui::TextColored(ImVec4(0.4f, 0.7f, 1, 1), "%s", model.commands().refusal().c_str());
  } else if (!st.command_text.empty()) {
    const ParseResult r = ParseCommand(st.command_text);
    if (r.ok()) ImGui::TextColored(ImVec4(0.4f, 0.9f, 0.4f, 1), "ok: %s", r.command->Text().c_str());
    else ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.3f, 1), "%s", r.error.c_str());
    const std::string hint = ArgumentHint(st.command_text);
    if (!hint.empty()) ImGui::TextDisabled("%s", hint.c_str());
  } else if (!model.commands().error().empty()) {
    ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1), "not sent: %s", model.commands().error().c_str());
  } else {
    std::string names = "commands:";
    for (const auto& spec : CommandSpecs()) names += std::string(" ") + spec.name;  // one list: the grammar's
    ImGui::TextDisabled("%s", names.c_str());
  }

  // Frequent actions, as buttons and as keyboard shortcuts (anywhere in the window); each asks
  // for confirmation, which Ctrl+K gives (Ctrl+Y is the text field's redo) and Escape withdraws.
  struct Action {
    const char* text;
    int key;  // with Ctrl; 0: none
  };
  static constexpr Action kActions[] = {{"arm", 0},     {"takeoff 10", 'T'}, {"hover", 'H'}, {"land", 'L'},
                                        {"return", 'R'}, {"mission", 0},     {"resume", 0},  {"disarm", 0}};
  const ImGuiIO& io = ImGui::GetIO();
  for (const Action& a : kActions) {
    if (ImGui::Button(a.text)) st.pending_confirmation = a.text;
    RegisterLastItem(ctx, std::string("button:") + a.text);
    if (a.key && ImGui::IsItemHovered()) ImGui::SetTooltip("Ctrl+%c", a.key);
    if (a.key && !model.replay() && io.KeyCtrl && ImGui::IsKeyPressed(a.key, false)) st.pending_confirmation = a.text;
    ImGui::SameLine();
  }
  // A tail-sitter's transitions (QGroundControl's VTOL transition buttons).
  if (const VehicleModel* v = model.selected(); v && v->state && v->state->vehicle_type == VehicleType::kTailSitter) {
    for (const char* text : {"transition fw", "transition mc"}) {
      if (ImGui::Button(text)) st.pending_confirmation = text;
      RegisterLastItem(ctx, std::string("button:") + text);
      ImGui::SameLine();
    }
  }
  ImGui::NewLine();
  if (!st.pending_confirmation.empty() && io.KeyCtrl && ImGui::IsKeyPressed('K', false)) {
    model.SubmitCommand(st.pending_confirmation, ctx.now);
    st.pending_confirmation.clear();
  }
  if (!st.pending_confirmation.empty() && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false))
    st.pending_confirmation.clear();
  if (!st.pending_confirmation.empty()) {
    ImGui::TextColored(ImVec4(1, 0.85f, 0.3f, 1), "send '%s' to %s?", st.pending_confirmation.c_str(),
                       model.selected_id().c_str());
    ImGui::SameLine();
    if (ImGui::Button("Confirm (Ctrl+K)")) {
      model.SubmitCommand(st.pending_confirmation, ctx.now);
      st.pending_confirmation.clear();
    }
    RegisterLastItem(ctx, "confirm");
    ImGui::SameLine();
    if (ImGui::Button("Cancel (Esc)")) st.pending_confirmation.clear();
    RegisterLastItem(ctx, "cancel");
  }
  EndDisabledBecause(ctx);
  DrawEmergencyStop(model, ctx);

  ImGui::Separator();
  // Acknowledgements of the most recent commands, newest first.
  int shown = 0;
  for (auto it = model.commands().sent().rbegin(); it != model.commands().sent().rend() && shown < 6; ++it, ++shown) {
    const SentCommand& c = *it;
    std::string state = c.gave_up ? "no answer, gave up" : !c.last_ack ? "waiting for ack" : std::string(Name(c.last_ack->result));
    if (c.tries > 1 && !c.acknowledged) state += " (try " + std::to_string(c.tries) + ")";
    const bool bad = c.gave_up || (c.last_ack && IsFailure(c.last_ack->result));
    // What the vehicle does on its own (a failsafe) is amber while it lasts, in a row of its own.
    const bool vehicle_active = c.vehicle_initiated && c.last_ack &&
                                (c.last_ack->result == CommandResult::kAccepted || c.last_ack->result == CommandResult::kInProgress);
    const ImVec4 colour = bad ? ImVec4(1, 0.45f, 0.35f, 1) : vehicle_active ? ImVec4(1, 0.75f, 0.2f, 1) : ImVec4(0.85f, 0.85f, 0.85f, 1);
    ImGui::TextColored(colour, "%s  %s%-12s  %s", c.vehicle_id.c_str(), c.vehicle_initiated ? "[vehicle] " : "",
                       c.text.c_str(), state.c_str());
    if (c.last_ack && c.last_ack->result == CommandResult::kInProgress) {
      ImGui::SameLine();
      ImGui::ProgressBar(c.last_ack->percent / 100.0f, ImVec2(120, 0));
    }
    if (c.last_ack && !c.last_ack->reason.empty()) {
      // The whole reason, wrapped: "failsafe land: ... (landing where it is)" must not end at "(landing".
      ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
      ImGui::Indent();
      ImGui::TextWrapped("%s", c.last_ack->reason.c_str());
      ImGui::Unindent();
      ImGui::PopStyleColor();
    }
  }
  ImGui::End();
}

}  // namespace uav::gcs

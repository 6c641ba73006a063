#pragma once
// A number an operator types, as editors should take it: decimal only, kept while typing, and
// applied when the field is left (Enter, Tab, a click elsewhere) only when it is finite and within
// its limits. A refused value leaves the old one in place and the field red, saying what was
// typed and the limits, until a good value is typed: nothing changes without a word.
#include <string>

#include "uav/gcs/ui_context.hpp"

namespace uav::gcs {

// True in the frame a typed value was applied to *value. `unit` ends the refusal ("m", "m/s").
bool NumberField(UiContext& ctx, const std::string& id, double* value, double min, double max, const char* format,
                 const char* unit, float width = -1);

// The refusal shown under a field ("" none), for panels that lay it out themselves.
const std::string& NumberFieldRefusal(const UiContext& ctx, const std::string& id);
// Every refusal of the fields whose ids start with `prefix` ("mission:"), one wrapped red line
// each: "alt:3: 1e9 is outside [1.0, 120.0] m; it stays 15.0 m".
void DrawNumberFieldRefusals(const UiContext& ctx, const std::string& prefix);

}  // namespace uav::gcs

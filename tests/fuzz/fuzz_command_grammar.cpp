// The command grammar (shared/command_grammar): what the GCS's command bar and the vehicle parse.
#include <string_view>

#include "fuzz_input.hpp"
#include "uav/shared/command_grammar.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const uav::ParseResult r = uav::ParseCommand(std::string_view(reinterpret_cast<const char*>(data), size));
  if (r.ok()) (void)r.command->Name();
  return 0;
}

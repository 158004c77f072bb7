// libFuzzer target for the toio notification decoders (run by scripts/fuzz-toio). The first byte
// picks the decoder, the rest is the notification, copied into a buffer of exactly its size so
// AddressSanitizer catches any read past it. Anything accepted must have the spec's length.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "robot_agent/toio_protocol.hpp"

using namespace robot_agent::toio;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t which = data[0] % 5;
  const std::vector<uint8_t> bytes(data + 1, data + size);
  switch (which) {
    case 0:
      if (const auto id = decode_id(bytes)) {
        const size_t expected = std::holds_alternative<PositionId>(*id.value)   ? 13
                                : std::holds_alternative<StandardId>(*id.value) ? 7
                                                                                : 1;
        if (bytes.size() != expected) std::abort();
      } else if (id.error.empty()) {
        std::abort();
      }
      break;
    case 1:
      if (const auto motor = decode_motor(bytes); motor && bytes.size() != 3) std::abort();
      break;
    case 2:
      if (const auto reply = decode_configuration(bytes); reply && bytes.size() < 3) std::abort();
      break;
    case 3:
      if (const auto battery = decode_battery(bytes); battery && *battery.value > 100) std::abort();
      break;
    case 4: (void)decode_button(bytes); break;
  }
  (void)to_hex(bytes);
  return 0;
}

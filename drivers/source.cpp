#include "drivers/source.hpp"

namespace probeless {

const char* to_string(SourceState s) {
  switch (s) {
    case SourceState::Streaming: return "streaming";
    case SourceState::NoDevice: return "no_device";
    case SourceState::NoSignal: return "no_signal";
    case SourceState::Stalled: return "stalled";
    case SourceState::Ended: return "ended";
  }
  return "unknown";
}

}  // namespace probeless

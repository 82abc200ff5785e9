#pragma once
// Polls `condition` every 10 ms until it holds or `timeout` passes; the last look decides. The
// outputs' tests wait on servers, encoders and clients in other threads with it. Ten seconds:
// only a failing test waits that long, and a loaded CI host can take several to start a
// GStreamer pipeline.
#include <chrono>
#include <thread>

namespace probeless::testing {

template <typename F>
bool eventually(F condition, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return condition();
}

}  // namespace probeless::testing

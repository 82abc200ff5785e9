#pragma once
// Marker detection off the processing thread: finding a ChArUco board in a 640x480 frame
// takes ~10 ms here (AnchorSim.ReanchoringGlidesAtTheBoundedRate prints it), a sixth of the
// 60 fps budget. A sighting is tied to the world through the tracker pose of the frame it was
// taken in, so it is as good when it arrives a frame or two later. One frame in flight: a
// frame offered while the worker is busy is not taken.
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>

#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::world {

class BoardDetector;

class MarkerWorker {
 public:
  struct Sighting {
    bool found = false;
    Pose T_world_tracker;  // the board's world in the tracker's, when found
    Pose T_world_camera;   // the frame's camera in the board's world, when found
  };

  explicit MarkerWorker(std::unique_ptr<BoardDetector> detector);
  ~MarkerWorker();
  MarkerWorker(const MarkerWorker&) = delete;
  MarkerWorker& operator=(const MarkerWorker&) = delete;

  // Starts a detection on a copy of `colour` unless one is running; returns whether it did.
  bool offer(const ImageRGB8& colour, const Pose& T_tracker_camera);
  // The newest finished detection, once (nullopt when none finished since the last call).
  std::optional<Sighting> take();
  // Blocks until the detection in flight (if any) has finished: for deterministic tests.
  void wait_idle();

 private:
  void run(std::stop_token stop);

  std::unique_ptr<BoardDetector> detector_;
  std::mutex mutex_;
  std::condition_variable_any changed_;
  std::optional<std::pair<ImageRGB8, Pose>> job_;
  bool busy_ = false;
  std::optional<Sighting> result_;
  std::jthread thread_;  // last: stopped and joined before the rest goes
};

}  // namespace probeless::world

#include "app/world/marker_worker.hpp"

#include <spdlog/spdlog.h>

#include "app/world/board_detector.hpp"

namespace probeless::world {

MarkerWorker::MarkerWorker(std::unique_ptr<BoardDetector> detector)
    : detector_(std::move(detector)), thread_([this](std::stop_token s) { run(s); }) {}

MarkerWorker::~MarkerWorker() {
  thread_.request_stop();
  changed_.notify_all();
}

bool MarkerWorker::offer(const ImageRGB8& colour, const Pose& T_tracker_camera) {
  {
    std::lock_guard lock(mutex_);
    if (busy_ || job_) return false;
    job_.emplace(colour, T_tracker_camera);
  }
  changed_.notify_all();
  return true;
}

std::optional<MarkerWorker::Sighting> MarkerWorker::take() {
  std::lock_guard lock(mutex_);
  return std::exchange(result_, std::nullopt);
}

void MarkerWorker::wait_idle() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return !busy_ && !job_; });
}

void MarkerWorker::run(std::stop_token stop) {
  while (true) {
    std::pair<ImageRGB8, Pose> job;
    {
      std::unique_lock lock(mutex_);
      if (!changed_.wait(lock, stop, [&] { return job_.has_value(); })) return;
      job = std::move(*job_);
      job_.reset();
      busy_ = true;
    }
    Sighting s;
    try {
      const BoardDetection d = detector_->detect(job.first);
      s.found = d.found;
      if (d.found) {
        s.T_world_camera = (d.T_camera_board * detector_->T_board_world()).inverse();
        s.T_world_tracker = s.T_world_camera * job.second.inverse();
      }
    } catch (const std::exception& e) {
      // A frame the detector refuses (its size) finds nothing; say it, keep the thread.
      spdlog::warn("marker detection: {}", e.what());
    }
    {
      std::lock_guard lock(mutex_);
      result_ = s;
      busy_ = false;
    }
    changed_.notify_all();
  }
}

}  // namespace probeless::world

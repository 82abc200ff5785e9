#include "app/pipeline/frame_finisher.hpp"

#include <stdexcept>
#include <utility>

#include "app/pipeline/thread_name.hpp"

namespace probeless {

FrameFinisher::FrameFinisher(FrameProcessor& processor, StageStats& stats, Publish publish,
                             Fail fail, int capacity)
    : processor_(processor),
      stats_(stats),
      publish_(std::move(publish)),
      fail_(std::move(fail)),
      capacity_(capacity),
      thread_([this](std::stop_token stop) { loop(stop); }) {
  if (capacity < 1) throw std::invalid_argument("FrameFinisher: capacity must be >= 1");
}

FrameFinisher::~FrameFinisher() {
  thread_.request_stop();
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
  // The queue's frames go with the members: each InFlight waits for its device work.
}

bool FrameFinisher::wait_until(std::stop_token stop, int at_most) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, stop, [&] { return stopped_ || on_the_way_ <= at_most; });
  return !stopped_ && !stop.stop_requested();
}

bool FrameFinisher::wait_for_room(std::stop_token stop) {
  return wait_until(std::move(stop), capacity_ - 1);
}

bool FrameFinisher::drain(std::stop_token stop) {
  return wait_until(std::move(stop), 0);
}

void FrameFinisher::push(std::unique_ptr<Submitted> frame) {
  {
    std::lock_guard lock(mutex_);
    if (on_the_way_ >= capacity_)
      throw std::logic_error("FrameFinisher::push: no room (wait_for_room first)");
    queue_.push_back(std::move(frame));
    ++on_the_way_;
  }
  changed_.notify_all();
}

int FrameFinisher::on_the_way() const {
  std::lock_guard lock(mutex_);
  return on_the_way_;
}

void FrameFinisher::loop(std::stop_token stop) {
  name_this_thread("pl-finish");
  while (true) {
    std::unique_ptr<Submitted> next;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, stop, [&] { return !queue_.empty(); });
      if (stop.stop_requested()) break;
      next = std::move(queue_.front());
      queue_.pop_front();
    }
    bool go_on = true;
    try {
      // finish() waits for the device and frees the frame's slot before the publish, so the
      // processing thread's next submit finds one idle once on_the_way_ has dropped.
      CompositeFrame out = processor_.finish(std::move(next->work), stats_);
      go_on = publish_(std::move(out), next->status, stop);
    } catch (const std::exception& e) {
      fail_(e.what());
      go_on = false;
    }
    next.reset();
    {
      std::lock_guard lock(mutex_);
      --on_the_way_;
      if (!go_on) stopped_ = true;
    }
    changed_.notify_all();
    if (!go_on) break;
  }
  std::lock_guard lock(mutex_);
  stopped_ = true;
  changed_.notify_all();
}

}  // namespace probeless

#include "app/pipeline/tracking_worker.hpp"

#include <stdexcept>
#include <utility>

#include "app/pipeline/thread_name.hpp"

namespace probeless {

TrackingWorker::TrackingWorker() : thread_([this](std::stop_token s) { loop(s); }) {}

TrackingWorker::~TrackingWorker() {
  thread_.request_stop();
  changed_.notify_all();
}

void TrackingWorker::submit(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    if (busy_) throw std::logic_error("TrackingWorker: submit() before wait()");
    job_ = std::move(job);
    busy_ = true;
  }
  changed_.notify_all();
}

void TrackingWorker::wait() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return !busy_; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void TrackingWorker::loop(std::stop_token stop) {
  name_this_thread("pl-tracking");
  while (true) {
    std::function<void()> job;
    {
      std::unique_lock lock(mutex_);
      if (!changed_.wait(lock, stop, [&] { return static_cast<bool>(job_); })) return;
      job = std::move(job_);
      job_ = nullptr;
    }
    std::exception_ptr error;
    try {
      job();
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard lock(mutex_);
      error_ = error;
      busy_ = false;
    }
    changed_.notify_all();
  }
}

}  // namespace probeless

#pragma once
// One job at a time on a thread of its own: the processing loop's tracker, so that frame
// N+1 is tracked while frame N is rendered, matted and composited (docs/performance.md: on two
// cores the frame path was tracking then render then matte in series, 6-8 ms of the tracker's
// CPU path beside idle PoCL and llvmpipe workers). submit() then wait(), strictly alternating.
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace probeless {

class TrackingWorker {
 public:
  TrackingWorker();
  ~TrackingWorker();
  TrackingWorker(const TrackingWorker&) = delete;
  TrackingWorker& operator=(const TrackingWorker&) = delete;

  // Starts `job` on the worker. The previous job must have been waited for.
  void submit(std::function<void()> job);
  // Until the job submitted last has returned; rethrows what it threw.
  void wait();

 private:
  void loop(std::stop_token stop);

  std::mutex mutex_;
  std::condition_variable_any changed_;
  std::function<void()> job_;
  bool busy_ = false;
  std::exception_ptr error_;
  std::jthread thread_;  // last: starts after the members it uses
};

}  // namespace probeless

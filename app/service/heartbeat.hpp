#pragma once
// Which of the service's threads are alive (issue #20 item 6): every thread whose hang would
// leave the appliance useless (processing, light, the output thread with its JPEG encoder,
// the HTTP and RTSP event loops) holds a Heartbeat and beats from its loop, idle or not (a
// timed wait or a loop timer). The watchdog (app/service/watchdog.hpp) sends WATCHDOG=1 only
// while every registered heartbeat is fresh, and /status names the stale ones.
//
// A thread that ends on purpose (the source ended, the light stage failed and says so in
// /status) drops its Heartbeat and is no longer watched.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace probeless {

class HeartbeatRegistry {
  struct Entry;

 public:
  // Registered while it lives; movable. beat() is one atomic store, from the owning thread.
  class Heartbeat {
   public:
    Heartbeat() = default;
    Heartbeat(Heartbeat&& other) noexcept;
    Heartbeat& operator=(Heartbeat&& other) noexcept;
    Heartbeat(const Heartbeat&) = delete;
    Heartbeat& operator=(const Heartbeat&) = delete;
    ~Heartbeat();
    void beat();
    explicit operator bool() const { return entry_ != nullptr; }  // registered

   private:
    friend class HeartbeatRegistry;
    Heartbeat(HeartbeatRegistry* registry, std::shared_ptr<Entry> entry)
        : registry_(registry), entry_(std::move(entry)) {}
    HeartbeatRegistry* registry_ = nullptr;
    std::shared_ptr<Entry> entry_;
  };

  // A heartbeat older than `stale_after` is stale.
  explicit HeartbeatRegistry(std::chrono::milliseconds stale_after);
  HeartbeatRegistry(const HeartbeatRegistry&) = delete;
  HeartbeatRegistry& operator=(const HeartbeatRegistry&) = delete;

  Heartbeat add(std::string name);  // fresh from now
  std::vector<std::string> stale() const;
  std::chrono::milliseconds stale_after() const { return stale_after_; }
  // {"stale_after_ms", "stale": [names], "threads": {name: {"age_ms"}}} for /status.
  nlohmann::json to_json() const;

  // Fault injection for the watchdog tests (`run --fault-hang THREAD:N`): the N-th beat of
  // the heartbeat called `name` blocks, wedging its thread where it beats, until
  // release_wedged() (the pipeline's stop(), so that the wedged thread can still be joined).
  void wedge_after(std::string name, std::int64_t beats);
  void release_wedged();

 private:
  void remove(const std::shared_ptr<Entry>& entry);
  void wedge(Entry& entry);

  std::chrono::milliseconds stale_after_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Entry>> entries_;
  std::string wedge_name_;
  std::int64_t wedge_after_beats_ = -1;
  bool released_ = false;
  std::condition_variable released_changed_;
};

using Heartbeat = HeartbeatRegistry::Heartbeat;

}  // namespace probeless

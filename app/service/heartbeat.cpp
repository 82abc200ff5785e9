#include "app/service/heartbeat.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>

#include "core/time.hpp"

namespace probeless {

struct HeartbeatRegistry::Entry {
  std::string name;
  std::atomic<TimestampNs> last_ns{0};
  std::atomic<std::int64_t> beats{0};
  bool wedge = false;  // fault injection: this entry's beats block after wedge_after_beats_
};

HeartbeatRegistry::Heartbeat::Heartbeat(Heartbeat&& other) noexcept
    : registry_(std::exchange(other.registry_, nullptr)), entry_(std::move(other.entry_)) {}

HeartbeatRegistry::Heartbeat& HeartbeatRegistry::Heartbeat::operator=(Heartbeat&& other) noexcept {
  if (this != &other) {
    if (registry_) registry_->remove(entry_);
    registry_ = std::exchange(other.registry_, nullptr);
    entry_ = std::move(other.entry_);
  }
  return *this;
}

HeartbeatRegistry::Heartbeat::~Heartbeat() {
  if (registry_) registry_->remove(entry_);
}

void HeartbeatRegistry::Heartbeat::beat() {
  if (!entry_) return;
  const std::int64_t n = ++entry_->beats;
  if (entry_->wedge && n >= registry_->wedge_after_beats_) registry_->wedge(*entry_);
  entry_->last_ns.store(monotonic_now_ns(), std::memory_order_relaxed);
}

HeartbeatRegistry::HeartbeatRegistry(std::chrono::milliseconds stale_after)
    : stale_after_(stale_after) {}

Heartbeat HeartbeatRegistry::add(std::string name) {
  auto entry = std::make_shared<Entry>();
  entry->name = std::move(name);
  entry->last_ns = monotonic_now_ns();
  std::lock_guard lock(mutex_);
  entry->wedge = !wedge_name_.empty() && entry->name == wedge_name_;
  entries_.push_back(entry);
  return Heartbeat(this, std::move(entry));
}

void HeartbeatRegistry::remove(const std::shared_ptr<Entry>& entry) {
  std::lock_guard lock(mutex_);
  std::erase(entries_, entry);
}

std::vector<std::string> HeartbeatRegistry::stale() const {
  const TimestampNs now = monotonic_now_ns();
  const TimestampNs limit = std::chrono::nanoseconds(stale_after_).count();
  std::vector<std::string> names;
  std::lock_guard lock(mutex_);
  for (const auto& e : entries_)
    if (now - e->last_ns.load(std::memory_order_relaxed) > limit) names.push_back(e->name);
  return names;
}

nlohmann::json HeartbeatRegistry::to_json() const {
  const TimestampNs now = monotonic_now_ns();
  nlohmann::json threads = nlohmann::json::object();
  {
    std::lock_guard lock(mutex_);
    for (const auto& e : entries_)
      threads[e->name] = {{"age_ms", (now - e->last_ns.load()) / 1'000'000}};
  }
  return {{"stale_after_ms", stale_after_.count()}, {"stale", stale()}, {"threads", threads}};
}

void HeartbeatRegistry::wedge_after(std::string name, std::int64_t beats) {
  std::lock_guard lock(mutex_);
  wedge_name_ = std::move(name);
  wedge_after_beats_ = beats;
  for (auto& e : entries_) e->wedge = e->name == wedge_name_;
}

void HeartbeatRegistry::release_wedged() {
  std::lock_guard lock(mutex_);
  released_ = true;
  released_changed_.notify_all();
}

void HeartbeatRegistry::wedge(Entry& entry) {
  std::unique_lock lock(mutex_);
  if (released_) return;
  spdlog::warn("fault injection: the {} thread hangs at its beat {}", entry.name,
               entry.beats.load());
  released_changed_.wait(lock, [&] { return released_; });
}

}  // namespace probeless

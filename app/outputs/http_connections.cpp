#include "app/outputs/http_connections.hpp"

#include <event2/buffer.h>
#include <event2/bufferevent.h>
#include <event2/event.h>
#include <event2/http.h>

#include <algorithm>
#include <vector>

namespace probeless {
namespace {

bufferevent* new_connection_cb(event_base*, void* arg) {
  return static_cast<HttpConnections*>(arg)->on_new_connection();
}
void sweep_cb(evutil_socket_t, short, void* arg) {
  static_cast<HttpConnections*>(arg)->sweep();
}

// evhttp's callbacks on a connection it still owns; its error callback is always set.
evhttp_connection* owner_of(bufferevent* bev) {
  bufferevent_data_cb read_cb = nullptr, write_cb = nullptr;
  bufferevent_event_cb event_cb = nullptr;
  void* arg = nullptr;
  bufferevent_getcb(bev, &read_cb, &write_cb, &event_cb, &arg);
  return event_cb != nullptr ? static_cast<evhttp_connection*>(arg) : nullptr;
}

}  // namespace

HttpConnections::HttpConnections(event_base* base, evhttp* http, HttpConnectionLimits limits,
                                 std::function<void()> on_sweep)
    : base_(base), limits_(limits), on_sweep_(std::move(on_sweep)) {
  sweep_event_ = event_new(base, -1, EV_PERSIST, sweep_cb, this);
  const auto ms = limits_.sweep_period.count();
  const timeval period{static_cast<time_t>(ms / 1000), static_cast<suseconds_t>(ms % 1000 * 1000)};
  event_add(sweep_event_, &period);
  evhttp_set_bevcb(http, new_connection_cb, this);
}

HttpConnections::~HttpConnections() {
  if (sweep_event_) event_free(sweep_event_);
  // evhttp has freed its connections by now: ours are the last references.
  for (auto& [bev, tracked] : tracked_) bufferevent_unlock(bev);
  tracked_.clear();
}

bufferevent* HttpConnections::on_new_connection() {
  release_closed();
  bufferevent* bev = bufferevent_socket_new(base_, -1, BEV_OPT_CLOSE_ON_FREE);
  if (bev == nullptr) return nullptr;  // evhttp then makes its own, untracked
  // Not a lock (the bufferevent is not thread-safe): a reference, dropped in release_closed().
  bufferevent_lock(bev);
  tracked_[bev] = {monotonic_now_ns(), false};
  ++counts_.accepted;
  counts_.open = tracked_.size();
  // Over the cap: the sweep, right after evhttp has set this one up, closes the oldest
  // connections still waiting for their headers (a slowloris' or idle ones before new ones).
  if (limits_.max_connections > 0 &&
      tracked_.size() > static_cast<std::size_t>(limits_.max_connections)) {
    event_active(sweep_event_, EV_TIMEOUT, 0);
  }
  return bev;
}

void HttpConnections::request_arrived(bufferevent* bev) {
  if (auto it = tracked_.find(bev); it != tracked_.end()) it->second.waiting_since = 0;
}

void HttpConnections::became_stream(bufferevent* bev) {
  if (auto it = tracked_.find(bev); it != tracked_.end()) {
    it->second.stream = true;
    it->second.waiting_since = 0;
  }
}

void HttpConnections::release_closed() {
  for (auto it = tracked_.begin(); it != tracked_.end();) {
    if (owner_of(it->first) != nullptr) {
      ++it;
      continue;
    }
    bufferevent_disable(it->first, EV_READ | EV_WRITE);
    bufferevent_unlock(it->first);  // the last reference: the socket is closed
    it = tracked_.erase(it);
  }
  counts_.open = tracked_.size();
}

void HttpConnections::close(bufferevent* bev) {
  if (evhttp_connection* conn = owner_of(bev)) evhttp_connection_free(conn);
}

void HttpConnections::sweep() {
  release_closed();
  const TimestampNs now = monotonic_now_ns();
  const TimestampNs deadline_ns = ms_to_ns(limits_.header_timeout.count());
  std::vector<std::pair<TimestampNs, bufferevent*>> waiting;
  std::vector<bufferevent*> late;
  for (auto& [bev, t] : tracked_) {
    if (t.stream) continue;
    if (t.waiting_since == 0) {
      // A response was being written; once it is out and evhttp reads again (keep-alive),
      // the connection waits for its next request's headers from now.
      const bool reading = (bufferevent_get_enabled(bev) & EV_READ) != 0;
      if (reading && evbuffer_get_length(bufferevent_get_output(bev)) == 0) t.waiting_since = now;
      continue;
    }
    if (limits_.header_timeout.count() > 0 && now - t.waiting_since > deadline_ns) {
      late.push_back(bev);
    } else {
      waiting.emplace_back(t.waiting_since, bev);
    }
  }
  for (bufferevent* bev : late) {
    close(bev);
    ++counts_.header_timeouts;
  }
  release_closed();
  if (limits_.max_connections > 0 &&
      tracked_.size() > static_cast<std::size_t>(limits_.max_connections)) {
    std::sort(waiting.begin(), waiting.end());
    const std::size_t over = tracked_.size() - static_cast<std::size_t>(limits_.max_connections);
    for (std::size_t i = 0; i < over && i < waiting.size(); ++i) {
      close(waiting[i].second);
      ++counts_.evicted;
    }
    release_closed();
  }
  if (on_sweep_) {
    on_sweep_();
    release_closed();  // what on_sweep_ freed (slow streams) is closed now, not a sweep later
  }
}

}  // namespace probeless

#pragma once
// One WHEP client of the WebRTC output (app/outputs/webrtc_output.hpp): its pipeline
//
//   appsrc (H.264 access units) ! rtph264pay ! capssetter ! webrtcbin
//
// negotiated against the client's offer in the constructor (blocking: the output's worker
// thread builds sessions one at a time), then fed the shared encoder's access units by
// push(). Private to app/outputs.
#include <gst/gst.h>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>

#include "app/outputs/gst_objects.hpp"
#include "app/outputs/webrtc_output.hpp"
#include "app/outputs/whep_offer.hpp"
#include "core/time.hpp"

namespace probeless::webrtc {

struct SessionHooks {
  std::function<void()> changed;          // the ICE state moved: the worker looks again
  std::function<void()> keyframe_wanted;  // a PLI from the client, or frames dropped
};

class Session {
 public:
  // Negotiates; throws WhepOfferError when webrtcbin refuses the offer (400), WebRtcError on
  // anything else (500). On return answer() holds the SDP with every ICE candidate.
  Session(std::string id, const std::string& offer, const WhepOfferChoice& format,
          const WebRtcConfig& config, SessionHooks hooks);
  ~Session();  // the pipeline to NULL: its threads have stopped when this returns
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const std::string& id() const { return id_; }
  const std::string& answer() const { return answer_; }

  // The encoder's thread: one access unit, `capture_ns` its capture time (CLOCK_MONOTONIC).
  // Until the first keyframe (and after a drop), delta frames are skipped: a decoder could
  // not use them.
  void push(GstBuffer* access_unit, TimestampNs capture_ns);

  // Failed or closed, a BYE from the client, not connected within `connect_timeout` of the
  // answer, ICE disconnected or no RTCP from the client for `disconnected_timeout`.
  // A pipeline error also ends the session (error() says which).
  bool finished(TimestampNs now, TimestampNs connect_timeout, TimestampNs disconnected_timeout);
  // The first error the session's pipeline posted; empty if none. The worker's thread.
  std::string error();
  std::uint64_t frames_sent() const { return sent_; }

  // webrtcbin's signals (public for the C callbacks).
  void on_ice_state();
  void on_gathering_state();
  void on_rtcp();  // any RTCP packet from the client
  void on_bye();

 private:
  void negotiate(const std::string& offer, const WhepOfferChoice& format,
                 const WebRtcConfig& config);

  std::string id_;
  SessionHooks hooks_;
  gst::Element pipeline_, src_, webrtc_, rtpbin_;
  std::string answer_;
  TimestampNs answered_ns_ = 0;
  std::atomic<int> ice_state_{0};                // GstWebRTCICEConnectionState
  std::atomic<TimestampNs> disconnected_ns_{0};  // when it became disconnected, 0: is not
  std::atomic<bool> ever_connected_{false};
  std::atomic<TimestampNs> connected_ns_{0};
  std::atomic<TimestampNs> last_heard_ns_{0};  // the client's last RTCP
  std::atomic<bool> bye_{false};
  std::mutex gather_mutex_;
  std::condition_variable gathered_cv_;
  bool gathered_ = false;
  bool need_keyframe_ = true;  // the encoder's thread only
  std::atomic<std::uint64_t> sent_{0};
  std::string failed_;
};

}  // namespace probeless::webrtc

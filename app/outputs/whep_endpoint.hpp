#pragma once
// The seam between the HTTP server, which speaks WHEP (RFC 9725 draft's HTTP side: POST an
// SDP offer, 201 with the answer and a resource URL, DELETE it), and the WebRTC output that
// makes the sessions (app/outputs/webrtc_output.hpp). The server knows nothing of GStreamer;
// the output nothing of HTTP.
#include <functional>
#include <string>
#include <string_view>
#include <utility>

namespace probeless {

struct WhepAnswer {
  int status = 201;        // 201 with `sdp`; else 400 (bad offer), 503 (full), 500
  std::string sdp;         // the answer, ICE candidates included (no trickle)
  std::string session_id;  // for the resource URL; empty unless 201
  std::string error;       // the reason, for the client, unless 201

  static WhepAnswer refusal(int status, std::string error) {
    WhepAnswer a;
    a.status = status;
    a.error = std::move(error);
    return a;
  }
};

class WhepEndpoint {
 public:
  using Done = std::function<void(WhepAnswer)>;
  virtual ~WhepEndpoint() = default;
  // Any thread, returns at once: `done` is called exactly once, on another thread, when the
  // answer (or the refusal) is ready. The offer has been size-checked by the caller.
  virtual void offer(std::string sdp, Done done) = 0;
  // Ends the session; false when there is none of that id.
  virtual bool close_session(std::string_view id) = 0;
};

}  // namespace probeless

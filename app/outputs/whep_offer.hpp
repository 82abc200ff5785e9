#pragma once
// What the WHEP endpoint checks of a client's SDP offer before any GStreamer object is made
// (docs/outputs.md "WebRTC (WHEP)"): a malformed or unservable offer becomes a 400 with the
// reason, never a webrtcbin error later. Pure: tested on plain strings.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace probeless {

// An offer larger than this is refused before it is read (a browser's video-only offer is
// 4-7 KB; every codec Chromium knows, with RTX and FEC, stays under 10 KB).
inline constexpr std::size_t kMaxWhepOfferBytes = std::size_t{16} * 1024;

struct WhepOfferError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The offer's H.264 format the answer takes: its payload type and the fmtp's
// profile-level-id (so the answer names a profile the client offered).
struct WhepOfferChoice {
  int payload_type = 0;
  std::string profile_level_id;  // "42e01f"
};

// Throws WhepOfferError naming what is wrong: not SDP, no video m-line, an audio or data
// m-line (only video is served), the client only sends, no ICE credentials or DTLS
// fingerprint (not a WebRTC offer), no H.264 with packetization-mode=1 (what rtph264pay
// sends). Among several H.264 formats: constrained baseline (what the encoder makes), then
// baseline, then any other profile.
WhepOfferChoice choose_whep_format(std::string_view sdp);

}  // namespace probeless

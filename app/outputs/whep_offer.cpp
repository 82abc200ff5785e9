#include "app/outputs/whep_offer.hpp"

#include <gst/sdp/sdp.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace probeless {
namespace {

struct SdpDeleter {
  void operator()(GstSDPMessage* m) const { gst_sdp_message_free(m); }
};

bool has_attribute(const GstSDPMessage* msg, const GstSDPMedia* media, const char* key) {
  return gst_sdp_media_get_attribute_val(media, key) != nullptr ||
         gst_sdp_message_get_attribute_val(msg, key) != nullptr;
}

// "packetization-mode=1;profile-level-id=42e01f" -> the value of `key`, or nullopt.
std::optional<std::string> fmtp_value(std::string_view params, std::string_view key) {
  while (!params.empty()) {
    const auto end = params.find(';');
    std::string_view item = params.substr(0, end);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    if (item.size() > key.size() && item.substr(0, key.size()) == key && item[key.size()] == '=')
      return std::string(item.substr(key.size() + 1));
    if (end == std::string_view::npos) break;
    params.remove_prefix(end + 1);
  }
  return std::nullopt;
}

// Lower is better: constrained baseline is what the encoder is asked for.
int profile_rank(const std::string& plid) {
  if (plid.size() != 6) return 3;
  if (plid.compare(0, 2, "42") == 0 && plid[2] == 'e') return 0;
  if (plid.compare(0, 2, "42") == 0) return 1;
  return 2;
}

}  // namespace

WhepOfferChoice choose_whep_format(std::string_view sdp) {
  if (sdp.empty()) throw WhepOfferError("empty offer");
  if (sdp.size() > kMaxWhepOfferBytes) throw WhepOfferError("offer too large");
  if (sdp.substr(0, 4) != "v=0\r" && sdp.substr(0, 4) != "v=0\n")
    throw WhepOfferError("not an SDP offer (it must start with v=0)");
  GstSDPMessage* raw = nullptr;
  gst_sdp_message_new(&raw);
  std::unique_ptr<GstSDPMessage, SdpDeleter> msg(raw);
  if (gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(sdp.data()),
                                   static_cast<guint>(sdp.size()), msg.get()) != GST_SDP_OK)
    throw WhepOfferError("the SDP does not parse");

  const GstSDPMedia* video = nullptr;
  for (guint i = 0; i < gst_sdp_message_medias_len(msg.get()); ++i) {
    const GstSDPMedia* m = gst_sdp_message_get_media(msg.get(), i);
    const std::string kind = gst_sdp_media_get_media(m) ? gst_sdp_media_get_media(m) : "";
    if (kind != "video")
      throw WhepOfferError("m=" + kind + ": only one video stream is served (no audio, no data)");
    if (video) throw WhepOfferError("more than one video m-line: one stream is served");
    video = m;
  }
  if (!video) throw WhepOfferError("no m=video line");
  if (gst_sdp_media_get_attribute_val(video, "sendonly") ||
      gst_sdp_media_get_attribute_val(video, "inactive"))
    throw WhepOfferError(
        "the video m-line must be recvonly or sendrecv (WHEP plays to the client)");
  if (!has_attribute(msg.get(), video, "ice-ufrag") || !has_attribute(msg.get(), video, "ice-pwd"))
    throw WhepOfferError("no ICE credentials (a=ice-ufrag, a=ice-pwd): not a WebRTC offer");
  if (!has_attribute(msg.get(), video, "fingerprint"))
    throw WhepOfferError("no DTLS fingerprint (a=fingerprint): not a WebRTC offer");

  // The formats from a=rtpmap and a=fmtp as written: GStreamer's SDP-to-caps helper turns
  // profile-level-id into a profile name and drops the level, which the answer must repeat.
  std::map<int, std::string> encoding, params;
  for (guint i = 0; i < gst_sdp_media_attributes_len(video); ++i) {
    const GstSDPAttribute* a = gst_sdp_media_get_attribute(video, i);
    if (!a->key || !a->value) continue;
    const std::string_view key = a->key;
    if (key != "rtpmap" && key != "fmtp") continue;
    const std::string_view value = a->value;
    const auto space = value.find(' ');
    if (space == std::string_view::npos) continue;
    const int pt = std::atoi(std::string(value.substr(0, space)).c_str());
    (key == "rtpmap" ? encoding : params)[pt] = std::string(value.substr(space + 1));
  }
  std::optional<WhepOfferChoice> best;
  int best_rank = 99;
  for (const auto& [pt, name] : encoding) {
    // Dynamic payload types: 96-127, and 35-63, which Chromium also takes when it runs out.
    if (!(pt >= 96 && pt <= 127) && !(pt >= 35 && pt <= 63)) continue;
    if (g_ascii_strncasecmp(name.c_str(), "H264/90000", 10) != 0) continue;
    const auto p = params.find(pt);
    const std::string fmtp = p == params.end() ? "" : p->second;
    if (fmtp_value(fmtp, "packetization-mode").value_or("0") != "1") continue;
    // RFC 6184's default profile-level-id is 42000a (baseline, level 1).
    std::string plid = fmtp_value(fmtp, "profile-level-id").value_or("42000a");
    std::transform(plid.begin(), plid.end(), plid.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (plid.size() != 6 || !std::all_of(plid.begin(), plid.end(),
                                         [](unsigned char c) { return std::isxdigit(c) != 0; }))
      continue;
    if (profile_rank(plid) < best_rank) {
      best_rank = profile_rank(plid);
      best = WhepOfferChoice{pt, plid};
    }
  }
  if (!best) throw WhepOfferError("no H.264 with packetization-mode=1 in the offer");
  return *best;
}

}  // namespace probeless

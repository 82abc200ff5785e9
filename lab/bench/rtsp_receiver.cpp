#include "lab/bench/rtsp_receiver.hpp"

#include <gst/app/gstappsink.h>

#include <memory>
#include <stdexcept>

namespace probeless::lab {

RtspReceiver::RtspReceiver(const std::string& url) {
  gst::ensure_gstreamer();
  // latency=0: no jitter-buffer delay on loopback. output-corrupt=false: nothing shown before
  // the first keyframe, as players do. thread-type=slice: FFmpeg's frame threading holds one
  // frame back per extra thread (33 ms at 30 Hz on two cores), a player's choice, not the
  // service's latency. sync=false: a frame is taken when decoded, not at its PTS.
  const std::string launch =
      "rtspsrc location=" + url +
      " protocols=tcp latency=0 ! rtph264depay ! avdec_h264 output-corrupt=false "
      "thread-type=slice ! videoconvert ! video/x-raw,format=RGB ! appsink name=sink "
      "sync=false max-buffers=4 drop=false";
  GError* raw = nullptr;
  pipeline_ = gst::Element::adopt_sink(gst_parse_launch(launch.c_str(), &raw));
  if (raw) {
    const std::unique_ptr<GError, gst::ErrorDeleter> error(raw);
    throw std::runtime_error("rtsp receiver: " + std::string(error->message) +
                             " (gstreamer1.0-plugins-good and -libav)");
  }
  sink_ = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(pipeline_.get()), "sink"));
  if (gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("rtsp receiver: cannot play " + url);
}

RtspReceiver::~RtspReceiver() {
  if (pipeline_) gst_element_set_state(pipeline_.get(), GST_STATE_NULL);
}

void RtspReceiver::throw_if_ended() {
  gst::throw_if_ended(pipeline_.get(), "rtsp receiver");
}

std::optional<ReceivedFrame> RtspReceiver::next(std::chrono::milliseconds timeout) {
  auto sample = gst::Sample::adopt(gst_app_sink_try_pull_sample(
      GST_APP_SINK(sink_.get()), static_cast<GstClockTime>(timeout.count()) * GST_MSECOND));
  if (!sample) {
    throw_if_ended();
    return std::nullopt;
  }
  ReceivedFrame out;
  out.decoded_ns = monotonic_now_ns();  // before the copy below, which is the bench's own
  out.image = gst::rgb_image_of(sample.get(), "rtsp receiver");
  return out;
}

}  // namespace probeless::lab

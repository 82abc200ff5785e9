#pragma once
// A real RTSP player for the RTSP output's tests, in-process: GStreamer's rtspsrc (RTSP and
// RTP over TCP or UDP on loopback), rtph264depay, avdec_h264 (FFmpeg's decoder, a different
// implementation from the x264 that encoded the stream), videoconvert to RGB, appsink.
#include <gst/app/gstappsink.h>
#include <gst/gst.h>

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "app/outputs/gst_objects.hpp"
#include "core/image.hpp"

namespace probeless::testing {

struct DecodedFrame {
  ImageRGB8 image;
  std::chrono::steady_clock::time_point received;
};

class RtspTestClient {
 public:
  // transport: "tcp" (interleaved in the RTSP connection, as `ffplay -rtsp_transport tcp`)
  // or "udp" (RTP/RTCP on UDP ports, what players try first).
  explicit RtspTestClient(const std::string& url, const std::string& transport = "tcp") {
    gst::ensure_gstreamer();
    // latency=0: no jitter-buffer delay on loopback, so what is measured is the server's.
    // output-corrupt=false: a client that joins between keyframes shows nothing until the
    // next one, as players do, instead of the decoder's guesses from missing references.
    // thread-type=slice: FFmpeg's default frame threading holds one frame per extra thread
    // back, which would be counted as the server's latency.
    const std::string launch = "rtspsrc location=" + url + " protocols=" + transport +
                               " latency=0 ! rtph264depay ! avdec_h264 output-corrupt=false "
                               "thread-type=slice ! videoconvert ! "
                               "video/x-raw,format=RGB ! appsink name=sink sync=false "
                               "max-buffers=8";
    GError* raw = nullptr;
    pipeline_ = gst::Element::adopt_sink(gst_parse_launch(launch.c_str(), &raw));
    if (raw) {
      std::string message = raw->message;
      g_error_free(raw);
      throw std::runtime_error("test client: " + message);
    }
    sink_ = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(pipeline_.get()), "sink"));
    gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING);
  }
  ~RtspTestClient() {
    if (pipeline_) gst_element_set_state(pipeline_.get(), GST_STATE_NULL);
  }
  RtspTestClient(const RtspTestClient&) = delete;
  RtspTestClient& operator=(const RtspTestClient&) = delete;

  // The next decoded frame, or nullopt after `timeout` or at the end of the stream.
  std::optional<DecodedFrame> next(std::chrono::milliseconds timeout) {
    auto sample = gst::Sample::adopt(gst_app_sink_try_pull_sample(
        GST_APP_SINK(sink_.get()), static_cast<GstClockTime>(timeout.count()) * GST_MSECOND));
    if (!sample) return std::nullopt;
    DecodedFrame out;
    out.received = std::chrono::steady_clock::now();
    out.image = gst::rgb_image_of(sample.get(), "test client");
    return out;
  }

  // The first error or end-of-stream message the pipeline posted, "" while there is none.
  std::string ended() {
    auto bus = gst::Bus::adopt(gst_element_get_bus(pipeline_.get()));
    GstMessage* msg = gst_bus_pop_filtered(
        bus.get(), static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_EOS));
    if (!msg) return "";
    std::string what = "eos";
    if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
      GError* error = nullptr;
      gst_message_parse_error(msg, &error, nullptr);
      what = std::string("error: ") + (error ? error->message : "?");
      if (error) g_error_free(error);
    }
    gst_message_unref(msg);
    return what;
  }

 private:
  gst::Element pipeline_;
  gst::Element sink_;
};

}  // namespace probeless::testing

#include "app/outputs/gst_objects.hpp"

#include <gst/video/video.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace probeless::gst {

void ensure_gstreamer() {
  static std::once_flag once;
  static std::string failure;
  std::call_once(once, [] {
    GError* raw = nullptr;
    if (!gst_init_check(nullptr, nullptr, &raw)) {
      std::unique_ptr<GError, ErrorDeleter> error(raw);
      failure = "GStreamer did not initialise: ";
      failure += error ? error->message : "no reason given";
    }
  });
  if (!failure.empty()) throw std::runtime_error(failure);
}

void throw_if_ended(GstElement* pipeline, const char* who) {
  const auto bus = Bus::adopt(gst_element_get_bus(pipeline));
  GstMessage* msg = gst_bus_pop_filtered(
      bus.get(), static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_EOS));
  if (!msg) return;
  std::string what = "the stream ended";
  if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
    GError* raw = nullptr;
    gst_message_parse_error(msg, &raw, nullptr);
    const std::unique_ptr<GError, ErrorDeleter> error(raw);
    what = error ? error->message : "an error";
  }
  gst_message_unref(msg);
  throw std::runtime_error(std::string(who) + ": " + what);
}

ImageRGB8 rgb_image_of(GstSample* sample, const char* who) {
  GstVideoInfo info;
  if (!gst_video_info_from_caps(&info, gst_sample_get_caps(sample)))
    throw std::runtime_error(std::string(who) + ": a sample without video caps");
  GstVideoFrame frame;
  if (!gst_video_frame_map(&frame, &info, gst_sample_get_buffer(sample), GST_MAP_READ))
    throw std::runtime_error(std::string(who) + ": cannot map a decoded frame");
  ImageRGB8 image(GST_VIDEO_INFO_WIDTH(&info), GST_VIDEO_INFO_HEIGHT(&info));
  const auto* data = static_cast<const std::uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0));
  const int stride = GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0);
  for (int y = 0; y < image.height(); ++y)
    std::memcpy(image.row(y), data + static_cast<std::ptrdiff_t>(y) * stride, image.row_elements());
  gst_video_frame_unmap(&frame);
  return image;
}

GstBuffer* wrap_rgb_frame(std::shared_ptr<const ImageRGB8> frame) {
  const std::size_t bytes = frame->size_bytes();
  const int width = frame->width(), height = frame->height();
  auto* keep = new std::shared_ptr<const ImageRGB8>(std::move(frame));
  GstBuffer* buffer = gst_buffer_new_wrapped_full(
      GST_MEMORY_FLAG_READONLY, const_cast<std::uint8_t*>((*keep)->data()), bytes, 0, bytes, keep,
      [](gpointer data) { delete static_cast<std::shared_ptr<const ImageRGB8>*>(data); });
  const int stride = width * 3;
  if (stride % 4 != 0) {
    gsize offset[GST_VIDEO_MAX_PLANES] = {0};
    gint strides[GST_VIDEO_MAX_PLANES] = {stride};
    gst_buffer_add_video_meta_full(buffer, GST_VIDEO_FRAME_FLAG_NONE, GST_VIDEO_FORMAT_RGB,
                                   static_cast<guint>(width), static_cast<guint>(height), 1, offset,
                                   strides);
  }
  return buffer;
}

FeedResult push_rgb_frame(GstAppSrc* src, RgbFeed& feed, std::shared_ptr<const ImageRGB8> frame,
                          TimestampNs capture_ns, GstClockTime base_time, int framerate,
                          int max_queued_frames) {
  const std::size_t frame_bytes = frame->size_bytes();
  if (frame->width() != feed.width || frame->height() != feed.height) {
    feed.width = frame->width();
    feed.height = frame->height();
    // A nominal constant rate, not 0/1 ("variable"): x264 given variable-rate input holds each
    // frame until the next one arrives (measured: push-to-decoded p50 41 ms at 30 Hz, against
    // 3 ms with a declared rate). The PTS still say when each frame was taken.
    auto caps = Caps::adopt(gst_caps_new_simple(
        "video/x-raw", "format", G_TYPE_STRING, "RGB", "width", G_TYPE_INT, feed.width, "height",
        G_TYPE_INT, feed.height, "framerate", GST_TYPE_FRACTION, framerate, 1, nullptr));
    gst_app_src_set_caps(src, caps.get());
    gst_app_src_set_max_bytes(src, frame_bytes * static_cast<std::size_t>(max_queued_frames));
  }
  if (gst_app_src_get_current_level_bytes(src) >=
      frame_bytes * static_cast<std::size_t>(max_queued_frames))
    return FeedResult::QueueFull;
  const auto capture = static_cast<GstClockTime>(capture_ns);
  GstClockTime pts = capture > base_time ? capture - base_time : GST_CLOCK_TIME_NONE;
  if (pts == GST_CLOCK_TIME_NONE ||
      (feed.last_pts != GST_CLOCK_TIME_NONE && pts <= feed.last_pts)) {
    // A repeated frame (NO SIGNAL) carries its old capture time, or none before the first
    // good frame: it is shown now.
    const GstClockTime now = static_cast<GstClockTime>(monotonic_now_ns()) - base_time;
    pts = feed.last_pts != GST_CLOCK_TIME_NONE ? std::max(feed.last_pts + 1, now) : now;
  }
  feed.last_pts = pts;
  GstBuffer* buffer = wrap_rgb_frame(std::move(frame));
  GST_BUFFER_PTS(buffer) = pts;
  return gst_app_src_push_buffer(src, buffer) == GST_FLOW_OK ? FeedResult::Sent
                                                             : FeedResult::Refused;
}

}  // namespace probeless::gst

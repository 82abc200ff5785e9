#include "app/outputs/gst_objects.hpp"

#include <fmt/format.h>
#include <gst/video/video.h>

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

bool has_element(const char* name) {
  return static_cast<bool>(ElementFactory::adopt(gst_element_factory_find(name)));
}

std::string missing_element(std::span<const RequiredElement> elements) {
  for (const RequiredElement& e : elements)
    if (!has_element(e.name))
      return fmt::format("GStreamer element {} not found: install {}", e.name, e.package);
  return {};
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

}  // namespace probeless::gst

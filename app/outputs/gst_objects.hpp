#pragma once
// Owning references to GLib/GStreamer objects (the RTSP output, app/outputs/rtsp_server.*).
// One template for every refcounted C handle: it holds one reference and drops it with the
// type's own unref function, so a failed construction half-way through cleans up by itself.
//
// GStreamer hands out *floating* references for new elements: adopt() them through
// adopt_sink(), which sinks the floating reference so that this wrapper owns a real one
// whether or not the element is later added to a bin (a bin takes its own reference).
#include <gst/gst.h>

#include <memory>
#include <span>
#include <string>
#include <utility>

#include "core/image.hpp"

namespace probeless::gst {

template <typename T, auto Unref>
class Ref {
 public:
  Ref() = default;
  // Takes over a reference the caller owns (a "transfer full" return value).
  static Ref adopt(T* ptr) { return Ref(ptr); }
  // Adds a reference of its own ("transfer none": a borrowed pointer).
  static Ref share(T* ptr) {
    if (ptr) g_object_ref(ptr);
    return Ref(ptr);
  }
  // For a new GstObject whose reference may be floating.
  static Ref adopt_sink(T* ptr) {
    if (ptr) gst_object_ref_sink(ptr);
    return Ref(ptr);
  }

  ~Ref() { reset(); }
  Ref(const Ref&) = delete;
  Ref& operator=(const Ref&) = delete;
  Ref(Ref&& other) noexcept : ptr_(std::exchange(other.ptr_, nullptr)) {}
  Ref& operator=(Ref&& other) noexcept {
    if (this != &other) {
      reset();
      ptr_ = std::exchange(other.ptr_, nullptr);
    }
    return *this;
  }

  T* get() const { return ptr_; }
  explicit operator bool() const { return ptr_ != nullptr; }
  void reset() {
    if (T* p = std::exchange(ptr_, nullptr)) Unref(p);
  }
  [[nodiscard]] T* release() { return std::exchange(ptr_, nullptr); }

 private:
  explicit Ref(T* ptr) : ptr_(ptr) {}
  T* ptr_ = nullptr;
};

using Element = Ref<GstElement, gst_object_unref>;
using ElementFactory = Ref<GstElementFactory, gst_object_unref>;
using Caps = Ref<GstCaps, gst_caps_unref>;
using Sample = Ref<GstSample, gst_sample_unref>;
using Bus = Ref<GstBus, gst_object_unref>;
using MainContext = Ref<GMainContext, g_main_context_unref>;
using MainLoop = Ref<GMainLoop, g_main_loop_unref>;
using Source = Ref<GSource, g_source_unref>;

// An owned GError: GStreamer and GLib report failures through one.
struct ErrorDeleter {
  void operator()(GError* e) const { g_error_free(e); }
};

// gst_init_check() once per process; throws std::runtime_error with GStreamer's reason.
void ensure_gstreamer();

// An element a pipeline needs and the Debian package that ships it.
struct RequiredElement {
  const char* name;
  const char* package;
};
bool has_element(const char* name);  // its factory is registered (after ensure_gstreamer())
// The first of `elements` not installed, as "GStreamer element NAME not found: install
// PACKAGE"; empty when all are. The outputs check their pipelines' elements with it so that a
// missing plugin is named with its package before a launch line fails without saying why.
std::string missing_element(std::span<const RequiredElement> elements);

// The packed RGB frame of a decoded video sample (an appsink's, caps video/x-raw RGB), copied
// row by row past GStreamer's stride; std::runtime_error naming `who` without video caps or
// when the buffer cannot be mapped. The RTSP clients' decode (tests, `bench latency`).
ImageRGB8 rgb_image_of(GstSample* sample, const char* who);

// Throws std::runtime_error("<who>: <reason>") when `pipeline`'s bus holds an error or the end
// of the stream (taking that message off the bus); returns otherwise. For the lab's receivers,
// which poll rather than run a main loop.
void throw_if_ended(GstElement* pipeline, const char* who);

// The frame's pixels as a new GstBuffer (transfer full) without a copy: the buffer holds a
// reference to the frame until GStreamer is done with it, and says the rows' stride in a
// video meta (GStreamer's default RGB stride is rounded up to 4 bytes; ours is not). The
// H.264 encoder's input.
GstBuffer* wrap_rgb_frame(std::shared_ptr<const ImageRGB8> frame);

}  // namespace probeless::gst

#include "app/outputs/gst_objects.hpp"

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

}  // namespace probeless::gst

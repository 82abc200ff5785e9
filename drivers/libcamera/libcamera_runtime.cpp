#include "drivers/libcamera/libcamera_runtime.hpp"

#include <fmt/format.h>
#include <libcamera/libcamera.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>

namespace probeless::libcam {

std::shared_ptr<libcamera::CameraManager> shared_camera_manager() {
  static std::mutex mutex;
  static std::weak_ptr<libcamera::CameraManager> current;
  std::lock_guard lock(mutex);
  if (auto manager = current.lock()) return manager;
  // libcamera logs every pipeline match and configuration at INFO on stderr; the service's
  // log says what matters. Its categories are made on first use and logSetLevel() only
  // reaches existing ones, so the level goes in through the variable its logger reads when
  // it is made (here, before any camera work); a LIBCAMERA_LOG_LEVELS already set wins.
  setenv("LIBCAMERA_LOG_LEVELS", "*:WARN", 0);
  auto manager = std::shared_ptr<libcamera::CameraManager>(new libcamera::CameraManager(),
                                                           [](libcamera::CameraManager* m) {
                                                             m->stop();
                                                             delete m;
                                                           });
  if (const int ret = manager->start(); ret < 0)
    throw std::runtime_error(fmt::format("libcamera CameraManager::start failed: error {}", ret));
  current = manager;
  return manager;
}

std::vector<CameraDescription> list_libcamera_cameras() {
  const auto manager = shared_camera_manager();
  std::vector<CameraDescription> out;
  for (const auto& camera : manager->cameras()) {
    CameraDescription d;
    d.id = camera->id();
    if (const auto model = camera->properties().get(libcamera::properties::Model)) d.model = *model;
    for (const auto& [id, info] : camera->controls()) {
      if (id == &libcamera::controls::ExposureTime) d.exposure_time = true;
      if (id == &libcamera::controls::AnalogueGain) d.analogue_gain = true;
      d.controls.push_back(fmt::format("{} {}", id->name(), info.toString()));  // "[min..max]"
    }
    // Formats without acquiring the camera (another process may stream from it).
    if (const auto config = camera->generateConfiguration({libcamera::StreamRole::Viewfinder});
        config && !config->empty()) {
      const libcamera::StreamFormats& formats = config->at(0).formats();
      for (const auto& pf : formats.pixelformats()) {
        const auto range = formats.range(pf);
        d.formats.push_back(
            fmt::format("{} {}..{}", pf.toString(), range.min.toString(), range.max.toString()));
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace probeless::libcam

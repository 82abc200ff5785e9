#include "drivers/openni2/openni2_runtime.hpp"

#include <OpenNI.h>

#include <mutex>

#include "drivers/platform/resident_libraries.hpp"

namespace probeless::openni2 {
namespace {

std::mutex runtime_mutex;
std::weak_ptr<OpenniRuntime> runtime_instance;

}  // namespace

std::string openni_error_text() {
  std::string text = openni::OpenNI::getExtendedError();
  // OpenNI indents its messages and ends them with blank lines.
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const auto last = text.find_last_not_of(" \t\r\n");
  text = text.substr(first, last - first + 1);
  for (char& c : text)
    if (c == '\n' || c == '\t') c = ' ';
  return text;
}

std::shared_ptr<OpenniRuntime> OpenniRuntime::acquire() {
  std::lock_guard lock(runtime_mutex);
  if (auto existing = runtime_instance.lock()) return existing;
  // Not make_shared: the constructor is private.
  std::shared_ptr<OpenniRuntime> fresh(new OpenniRuntime());
  runtime_instance = fresh;
  return fresh;
}

OpenniRuntime::OpenniRuntime() {
  if (openni::OpenNI::initialize() != openni::STATUS_OK) {
    throw OpenniError(
        "OpenNI2 did not initialise (drivers beside libOpenNI2 in OpenNI2/Drivers, "
        "/etc/openni2/OpenNI.ini): " +
        openni_error_text());
  }
  // OpenNI dlcloses its device drivers (OpenNI2/Drivers/lib*.so) in shutdown(); their globals
  // outlive it (see resident_libraries.hpp), and the next initialise would load fresh copies.
  // The drivers are whatever OpenNI found in its repository directory (OpenNI.ini), by default
  // OpenNI2/Drivers beside libOpenNI2.
  platform::keep_loaded_until_exit([](std::string_view path) {
    return path.find("/OpenNI2/Drivers/") != std::string_view::npos;
  });
}

OpenniRuntime::~OpenniRuntime() {
  openni::OpenNI::shutdown();
}

const char* pixel_format_name(int f) {
  switch (f) {
    case openni::PIXEL_FORMAT_DEPTH_1_MM:
      return "DEPTH_1_MM";
    case openni::PIXEL_FORMAT_DEPTH_100_UM:
      return "DEPTH_100_UM";
    case openni::PIXEL_FORMAT_SHIFT_9_2:
      return "SHIFT_9_2";
    case openni::PIXEL_FORMAT_SHIFT_9_3:
      return "SHIFT_9_3";
    case openni::PIXEL_FORMAT_RGB888:
      return "RGB888";
    case openni::PIXEL_FORMAT_YUV422:
      return "YUV422";
    case openni::PIXEL_FORMAT_GRAY8:
      return "GRAY8";
    case openni::PIXEL_FORMAT_GRAY16:
      return "GRAY16";
    case openni::PIXEL_FORMAT_JPEG:
      return "JPEG";
    case openni::PIXEL_FORMAT_YUYV:
      return "YUYV";
  }
  return "unknown";
}

std::string describe(const VideoModeInfo& m) {
  return std::to_string(m.width) + "x" + std::to_string(m.height) + "@" + std::to_string(m.fps) +
         " " + m.pixel_format;
}

std::vector<DeviceListing> list_openni_devices() {
  const auto runtime = OpenniRuntime::acquire();
  openni::Array<openni::DeviceInfo> infos;
  openni::OpenNI::enumerateDevices(&infos);
  std::vector<DeviceListing> out;
  for (int i = 0; i < infos.getSize(); ++i) {
    const openni::DeviceInfo& info = infos[i];
    DeviceListing d{info.getUri(),
                    info.getVendor(),
                    info.getName(),
                    static_cast<std::uint16_t>(info.getUsbVendorId()),
                    static_cast<std::uint16_t>(info.getUsbProductId()),
                    {},
                    {}};
    openni::Device device;
    if (device.open(info.getUri()) != openni::STATUS_OK) {
      d.error = openni_error_text();
    } else {
      const std::pair<openni::SensorType, const char*> sensors[] = {
          {openni::SENSOR_DEPTH, "depth"},
          {openni::SENSOR_COLOR, "colour"},
          {openni::SENSOR_IR, "ir"}};
      for (const auto& [type, label] : sensors) {
        const openni::SensorInfo* sensor = device.getSensorInfo(type);
        if (!sensor) continue;
        const auto& modes = sensor->getSupportedVideoModes();
        for (int m = 0; m < modes.getSize(); ++m) {
          d.modes.push_back({label, modes[m].getResolutionX(), modes[m].getResolutionY(),
                             modes[m].getFps(), pixel_format_name(modes[m].getPixelFormat())});
        }
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace probeless::openni2

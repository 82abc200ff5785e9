#pragma once
// The process's one libcamera::CameraManager (libcamera aborts when a second one is made),
// shared by every libcamera source and by `probeless devices`, and started once; plus the
// camera listing for `probeless devices`.
#include <memory>
#include <string>
#include <vector>

namespace libcamera {
class CameraManager;
}

namespace probeless::libcam {

// The running manager, made and started on first use and stopped when the last holder lets
// go. Throws std::runtime_error when CameraManager::start() fails. libcamera's own log is
// turned down to warnings unless LIBCAMERA_LOG_LEVELS says otherwise.
std::shared_ptr<libcamera::CameraManager> shared_camera_manager();

struct CameraDescription {
  std::string id;
  std::string model;                  // properties::Model, when the pipeline says
  bool exposure_time = false;         // controls::ExposureTime is offered
  bool analogue_gain = false;         // controls::AnalogueGain is offered
  std::vector<std::string> controls;  // "Name [min..max]" for every control
  std::vector<std::string> formats;   // "NAME WxH..WxH" for the viewfinder role
};

// Every camera the manager knows now. Throws as shared_camera_manager().
std::vector<CameraDescription> list_libcamera_cameras();

}  // namespace probeless::libcam

#include "lab/calib/camera_toml.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "base/atomic_file.hpp"
#include "core/camera/ocam.hpp"
#include "core/camera/pinhole.hpp"
#include "drivers/replay/calibration_file.hpp"

namespace probeless::calib {
namespace {

// An OCamCalib file is a few lines of numbers; anything far larger is not one.
constexpr std::uintmax_t kMaxOcamFileBytes = 1 << 20;

std::string fisheye_table(const std::shared_ptr<const CameraModel>& fisheye) {
  RigCalibration rig;
  rig.fisheye = fisheye;
  const std::string text = to_toml(rig);
  const auto begin = text.find("[fisheye]\n");
  const auto end = text.find("\n[extrinsics]");
  return "# probeless fisheye calibration: the [fisheye] table of a rig calibration\n"
         "# (docs/camera-models.md); write it into the rig's calibration.toml.\n\n" +
         text.substr(begin, end - begin) + "\n";
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  if (!write_file_atomically(path, text))
    throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

std::string write_camera_toml(const std::filesystem::path& path,
                              std::shared_ptr<const CameraModel> camera) {
  const auto* pinhole = dynamic_cast<const PinholeCamera*>(camera.get());
  if (std::filesystem::exists(path)) {
    RigCalibration rig;
    try {
      rig = replay::load_rig_calibration(path);
    } catch (const std::exception& e) {
      throw std::runtime_error(path.string() +
                               " exists and is not a rig calibration to add the camera to (" +
                               e.what() + "); remove it or name another file");
    }
    if (pinhole) {
      rig.rgb = *pinhole;
    } else {
      rig.fisheye = std::move(camera);
      rig.fisheye_file.clear();
    }
    write_rig_toml(path, rig);
    return std::string("replaced the ") + (pinhole ? "colour camera" : "fisheye") + " in " +
           path.string();
  }
  if (pinhole) {
    RigCalibration rig;
    rig.rgb = *pinhole;
    write_rig_toml(path, rig);
    return "wrote " + path.string() + " (an RGB-D-only rig calibration)";
  }
  write_text(path, fisheye_table(camera));
  return "wrote " + path.string() + " (the [fisheye] table of a rig calibration)";
}

void write_rig_toml(const std::filesystem::path& path, const RigCalibration& rig) {
  write_text(path, to_toml(rig));
}

std::shared_ptr<const CameraModel> read_ocam_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error(path.string() + ": no such OCamCalib file");
  if (size > kMaxOcamFileBytes)
    throw std::runtime_error(path.string() + ": " + std::to_string(size) +
                             " bytes is too large for an OCamCalib calib_results.txt");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw std::runtime_error(path.string() + ": cannot read");
  return std::make_shared<OCamCamera>(OCamCamera::parse(text.str(), path.string()));
}

}  // namespace probeless::calib

#include "drivers/replay/calibration_file.hpp"

#include <fstream>
#include <sstream>

#include "core/camera/ocam.hpp"
#include "core/error.hpp"

namespace probeless::replay {
namespace {

std::string read_whole_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path.string(), 0, "cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

RigCalibration load_rig_calibration(const std::filesystem::path& toml_path) {
  RigCalibration c = parse_rig_calibration(read_whole_file(toml_path), toml_path.string());
  if (!c.fisheye && !c.fisheye_file.empty()) {
    const std::filesystem::path ocam = toml_path.parent_path() / c.fisheye_file;
    c.fisheye = std::make_shared<OCamCamera>(OCamCamera::parse(read_whole_file(ocam), ocam.string()));
  }
  return c;
}

RigCalibration self_contained(RigCalibration calibration) {
  if (calibration.fisheye) calibration.fisheye_file.clear();
  return calibration;
}

}  // namespace probeless::replay

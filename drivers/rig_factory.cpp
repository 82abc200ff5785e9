#include "drivers/rig_factory.hpp"

#include <stdexcept>

#include "drivers/openni2/openni2_rig.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/replay/playback.hpp"
#include "drivers/replay/replay_source.hpp"
#include "drivers/replay/tum_source.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/v4l2/v4l2_fisheye_source.hpp"
#ifdef PROBELESS_HAVE_LIBCAMERA
#include "drivers/libcamera/libcamera_fisheye_source.hpp"
#endif

namespace probeless {
namespace {

struct DirAndOptions {
  std::string dir;
  std::string options;
};

// "DIR?opts": the options follow the last '?' (a directory name rarely holds one).
DirAndOptions split_dir(std::string_view rest, std::string_view scheme) {
  const std::size_t q = rest.rfind('?');
  DirAndOptions out{std::string(rest.substr(0, q)),
                    q == std::string_view::npos ? std::string() : std::string(rest.substr(q + 1))};
  if (out.dir.empty()) {
    throw std::invalid_argument("source '" + std::string(scheme) + ":' needs a directory (" +
                                std::string(scheme) + ":DIR)");
  }
  return out;
}

// Takes `calibration=FILE` out of a fisheye spec's options (it is the rig's, not the
// camera's); the rest goes to the camera.
std::string take_calibration(std::string& fisheye_spec) {
  const std::size_t q = fisheye_spec.rfind('?');
  if (q == std::string::npos) return {};
  std::string kept, calibration;
  std::size_t pos = q + 1;
  while (pos <= fisheye_spec.size()) {
    const std::size_t end = std::min(fisheye_spec.find_first_of(",&", pos), fisheye_spec.size());
    const std::string item = fisheye_spec.substr(pos, end - pos);
    if (item.starts_with("calibration=")) {
      calibration = item.substr(12);
    } else if (!item.empty()) {
      kept += (kept.empty() ? "" : "&") + item;
    }
    pos = end + 1;
  }
  fisheye_spec = fisheye_spec.substr(0, q) + (kept.empty() ? "" : "?" + kept);
  return calibration;
}

// RGBD_SPEC+FISHEYE_SPEC: the RGB-D stream (and calibration) of one rig with another fisheye.
Rig open_combined_rig(std::string_view rgbd_spec, std::string fisheye_spec) {
  const std::string calibration = take_calibration(fisheye_spec);
  Rig rig = open_rig(rgbd_spec);
  rig.fisheye = open_fisheye_source(fisheye_spec);
  // The objects still stand in the RGB-D rig's world, but the light comes from a fisheye in
  // another room than the synthetic rig's.
  rig.scene.room.reset();
  if (!calibration.empty()) rig.calibration = replay::load_rig_calibration(calibration);
  return rig;
}

}  // namespace

std::string rig_spec_help() {
  return "sim, sim:<options>, replay:DIR[?realtime=0,loop=1,rebase=1,stamp=1], "
         "tum:DIR[?realtime=0,loop=1,rebase=1,stamp=1,calibration=FILE], "
         "v4l2:DEVICE[?size=WxH&fps=N&calibration=FILE...], RGBD_SPEC+v4l2:DEVICE[?...], "
         "libcamera:[CAMERA_ID][?size=WxH&format=NAME&calibration=FILE...], "
         "RGBD_SPEC+libcamera:[CAMERA_ID][?...], "
         "openni2:[URI][?size=WxH&fps=N...], openni2:FILE.oni[?speed=X&repeat=0|1]";
}

std::unique_ptr<FisheyeSource> open_fisheye_source(std::string_view spec) {
  if (spec.starts_with("v4l2:")) {
    return std::make_unique<v4l2::V4l2FisheyeSource>(v4l2::parse_v4l2_options(spec.substr(5)));
  }
  if (spec.starts_with("libcamera:")) {
#ifdef PROBELESS_HAVE_LIBCAMERA
    return std::make_unique<libcam::LibcameraFisheyeSource>(
        libcam::parse_libcamera_options(spec.substr(10)));
#else
    throw std::invalid_argument("source '" + std::string(spec) +
                                "': this build has no libcamera (libcamera-dev was not found "
                                "when it was configured; docs/boards.md)");
#endif
  }
  throw std::invalid_argument("unknown fisheye source '" + std::string(spec) +
                              "'; valid: v4l2:DEVICE[?options], libcamera:[CAMERA_ID][?options]");
}

Rig open_rig(std::string_view spec) {
  // A '+' joins an RGB-D rig and a fisheye; none of the schemes' own options uses one.
  if (const std::size_t plus = spec.find('+'); plus != std::string_view::npos) {
    return open_combined_rig(spec.substr(0, plus), std::string(spec.substr(plus + 1)));
  }
  const std::size_t colon = spec.find(':');
  const std::string_view scheme = spec.substr(0, colon);
  const std::string_view rest =
      colon == std::string_view::npos ? std::string_view{} : spec.substr(colon + 1);
  if (scheme == "sim") return sim::make_sim_rig(sim::parse_sim_options(rest));
  if (scheme == "replay") {
    const DirAndOptions d = split_dir(rest, scheme);
    return replay::open_replay_rig(d.dir, replay::parse_playback_options(d.options, nullptr));
  }
  if (scheme == "tum") {
    const DirAndOptions d = split_dir(rest, scheme);
    std::vector<std::pair<std::string, std::string>> extra;
    const replay::PlaybackOptions options = replay::parse_playback_options(d.options, &extra);
    std::string calibration;
    for (const auto& [key, value] : extra) {
      if (key != "calibration") {
        throw std::invalid_argument("tum: unknown option '" + key +
                                    "' (known: realtime, loop, rebase, stamp, calibration)");
      }
      calibration = value;
    }
    return replay::open_tum_rig(d.dir, options, calibration);
  }
  // The RGB-D camera through OpenNI2 (docs/drivers.md "OpenNI2 RGB-D"); with a fisheye:
  // "openni2:...+v4l2:...".
  if (scheme == "openni2") return openni2::open_openni2_rig(rest);
  // A V4L2 or libcamera camera is a fisheye only: until an RGB-D driver exists the RGB-D stream is
  // the synthetic rig's (docs/drivers.md "Spec").
  if (scheme == "v4l2" || scheme == "libcamera") return open_combined_rig("sim", std::string(spec));
  throw std::invalid_argument("unknown source '" + std::string(spec) +
                              "'; valid: " + rig_spec_help());
}

}  // namespace probeless

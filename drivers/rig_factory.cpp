#include "drivers/rig_factory.hpp"

#include <stdexcept>

#include "drivers/replay/playback.hpp"
#include "drivers/replay/replay_source.hpp"
#include "drivers/replay/tum_source.hpp"
#include "drivers/sim/sim_rig.hpp"

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

}  // namespace

std::string rig_spec_help() {
  return "sim, sim:<options>, replay:DIR[?realtime=0,loop=1,rebase=1], "
         "tum:DIR[?realtime=0,loop=1,calibration=FILE]";
}

Rig open_rig(std::string_view spec) {
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
                                    "' (known: realtime, loop, rebase, calibration)");
      }
      calibration = value;
    }
    return replay::open_tum_rig(d.dir, options, calibration);
  }
  throw std::invalid_argument("unknown source '" + std::string(spec) + "'; valid: " +
                              rig_spec_help());
}

}  // namespace probeless

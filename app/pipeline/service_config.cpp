#include "app/pipeline/service_config.hpp"

#include <arpa/inet.h>
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "app/outputs/display/display_mode.hpp"
#include "app/pipeline/board_file.hpp"
#include "core/board_spec.hpp"
#include "core/error.hpp"
#include "core/toml_reader.hpp"
#include "drivers/trigger/gpio_strobe.hpp"

namespace probeless {
namespace {

bool is_ip_literal(const std::string& text) {
  unsigned char buf[16];
  return inet_pton(AF_INET, text.c_str(), buf) == 1 || inet_pton(AF_INET6, text.c_str(), buf) == 1;
}

// [webrtc] (app/outputs/webrtc_output.hpp).
void parse_webrtc(const TomlReader& r, const toml::table& t, WebRtcConfig& c) {
  r.only(
      t, "[webrtc]",
      {"enabled", "ice_addresses", "max_sessions", "gather_timeout_ms", "disconnected_timeout_s"});
  r.get(t, "enabled", c.enabled);
  if (const toml::node* list = t.get("ice_addresses")) {
    const auto* arr = list->as_array();
    if (!arr) r.fail(list, "ice_addresses: expected an array of IP addresses");
    c.ice_addresses.clear();
    for (const auto& item : *arr) {
      const auto* text = item.as_string();
      if (!text || !is_ip_literal(text->get()))
        r.fail(&item, "ice_addresses: expected IP addresses such as \"127.0.0.1\" or \"::1\"");
      c.ice_addresses.push_back(text->get());
    }
  }
  r.get(t, "max_sessions", c.max_sessions);
  if (c.max_sessions < 1 || c.max_sessions > 64)
    r.fail(t.get("max_sessions"), "max_sessions must be 1..64");
  r.get(t, "gather_timeout_ms", c.gather_timeout_ms);
  if (c.gather_timeout_ms < 100 || c.gather_timeout_ms > 30000)
    r.fail(t.get("gather_timeout_ms"), "gather_timeout_ms must be 100..30000");
  r.get(t, "disconnected_timeout_s", c.disconnected_timeout_s);
  // Above RTP's RTCP interval: GStreamer's WHEP clients report every 5 s (+-50 %) by default,
  // browsers every second.
  if (c.disconnected_timeout_s < 8 || c.disconnected_timeout_s > 3600)
    r.fail(t.get("disconnected_timeout_s"), "disconnected_timeout_s must be 8..3600");
}

// [http]'s access keys (app/outputs/http_access.hpp): a secret that is required by the chosen
// scheme but empty is an error, not an open door.
void parse_http_access(const TomlReader& r, const toml::table& t, HttpAccessConfig& access) {
  if (const toml::node* hosts = t.get("allowed_hosts")) {
    const auto* arr = hosts->as_array();
    if (!arr) r.fail(hosts, "allowed_hosts: expected an array of host names");
    access.allowed_hosts.clear();
    for (const auto& item : *arr) {
      const auto* name = item.as_string();
      if (!name || name->get().empty()) r.fail(&item, "allowed_hosts: expected non-empty strings");
      access.allowed_hosts.push_back(name->get());
    }
  }
  std::string auth = "none";
  r.get(t, "auth", auth);
  try {
    access.auth = parse_http_auth(auth);
  } catch (const std::invalid_argument& e) {
    r.fail(t.get("auth"), e.what());
  }
  r.get(t, "user", access.user);
  r.get(t, "password", access.password);
  r.get(t, "token", access.token);
  r.get(t, "cors_origin", access.cors_origin);
  r.get(t, "max_streams_per_peer", access.max_streams_per_peer);
  if (access.auth == HttpAuth::Basic && (access.user.empty() || access.password.empty()))
    r.fail(t.get("auth"), "auth = \"basic\" needs a non-empty user and password");
  if (access.auth == HttpAuth::Bearer && access.token.size() < 16)
    r.fail(t.get("auth"), "auth = \"bearer\" needs a token of at least 16 characters");
  if (access.max_streams_per_peer < 0)
    r.fail(t.get("max_streams_per_peer"), "max_streams_per_peer must be >= 0 (0: no cap)");
}

ObjectConfig parse_object(const TomlReader& r, const toml::table& t) {
  r.only(
      t, "[[object]]",
      {"shape", "model", "position", "yaw_deg", "scale", "color", "material", "roughness", "ior"});
  ObjectConfig o;
  r.get(t, "shape", o.shape);
  r.get(t, "model", o.model);
  if (t.get("position")) {
    Eigen::Vector3d p;
    r.get_vector<3>(t, "position", p);
    o.position = p;
  }
  r.get(t, "yaw_deg", o.yaw_deg);
  r.get(t, "scale", o.scale);
  r.get_vector<3>(t, "color", o.colour);
  static const std::set<std::string> shapes{"pawn", "sphere", "box"};
  if (o.model.empty() && !shapes.contains(o.shape))
    r.fail(t.get("shape"), "shape '" + o.shape + "' is not one of pawn, sphere, box");
  if (!(o.scale > 0)) r.fail(t.get("scale"), "scale must be positive");
  r.get(t, "material", o.material);
  r.get(t, "roughness", o.roughness);
  r.get(t, "ior", o.ior);
  static const std::set<std::string> materials{"lambert", "mirror",  "metal",
                                               "glass",   "diffuse", "prt"};
  if (!materials.contains(o.material))
    r.fail(t.get("material"), "material '" + o.material +
                                  "' is not one of lambert, mirror, metal, glass, diffuse, prt");
  if (!(o.roughness >= 0 && o.roughness <= 1))
    r.fail(t.get("roughness"), "roughness must be in [0, 1]");
  if (!(o.ior > 0 && o.ior < 5)) r.fail(t.get("ior"), "ior must be in (0, 5)");
  return o;
}

}  // namespace

std::vector<ObjectConfig> default_objects() {
  // Beside each other across the table's anchor, 0.3 m apart: both visible from the orbit.
  ObjectConfig sphere;
  sphere.shape = "sphere";
  sphere.material = "mirror";
  sphere.colour = {0.95f, 0.95f, 0.95f};  // polished steel reflects ~60-95 %; chrome-like
  sphere.anchor_offset = Eigen::Vector3d(-0.15, 0.0, 0.0);
  ObjectConfig pawn;
  pawn.shape = "pawn";
  pawn.material = "prt";
  pawn.colour = {0.75f, 0.18f, 0.12f};
  pawn.anchor_offset = Eigen::Vector3d(0.15, 0.0, 0.0);
  return {sphere, pawn};
}

namespace {

ServiceConfig parse_service_table(const TomlReader& r, const toml::table& root) {
  ServiceConfig c;
  r.only(root, "the top level",
         {"source", "object", "ground", "occlusion", "http", "output", "opencl", "pipeline",
          "bracket", "light", "display", "rtsp", "webrtc", "board", "about", "tracking", "world"});
  r.get(root, "board", c.board);
  if (auto* t = r.optional_table(root, "about")) {
    r.only(*t, "[about]", {"name", "summary"});
    r.get(*t, "name", c.about_name);
    std::string summary;
    r.get(*t, "summary", summary);
  }
  if (auto* t = r.optional_table(root, "source")) {
    r.only(*t, "[source]", {"rig"});
    r.get(*t, "rig", c.source);
  }
  if (const toml::node* node = root.get("object")) {
    const toml::array* arr = node->as_array();
    if (!arr || !arr->is_array_of_tables()) r.fail(node, "object: expected [[object]] tables");
    c.objects.clear();
    for (const auto& item : *arr) c.objects.push_back(parse_object(r, *item.as_table()));
  }
  if (auto* t = r.optional_table(root, "occlusion")) {
    r.only(*t, "[occlusion]", {"method", "stabilise", "near_occluders", "beyond_range_m"});
    r.get(*t, "method", c.occlusion_method);
    r.get(*t, "stabilise", c.occlusion_stabilise);
    r.get(*t, "near_occluders", c.occlusion_near_occluders);
    r.get(*t, "beyond_range_m", c.occlusion_beyond_range_m);
    const double far = c.occlusion_beyond_range_m;
    if (!(far == 0 || (far >= 0.5 && far <= 20)))
      r.fail(t->get("beyond_range_m"), "beyond_range_m must be 0 (off) or 0.5..20 metres");
  }
  if (auto* t = r.optional_table(root, "tracking")) {
    r.only(*t, "[tracking]",
           {"method", "min_depth_m", "max_depth_m", "device", "rolling_shutter_readout_s"});
    r.get(*t, "method", c.tracking.method);
    r.get(*t, "min_depth_m", c.tracking.min_depth_m);
    r.get(*t, "max_depth_m", c.tracking.max_depth_m);
    r.get(*t, "device", c.tracking.device);
    r.get(*t, "rolling_shutter_readout_s", c.tracking.rolling_shutter_readout_s);
    static const std::set<std::string> methods{"dense", "truth", "off"};
    if (!methods.contains(c.tracking.method))
      r.fail(t->get("method"),
             "method '" + c.tracking.method + "' is not one of \"dense\", \"truth\", \"off\"");
    if (!(c.tracking.min_depth_m > 0 && c.tracking.min_depth_m < c.tracking.max_depth_m &&
          c.tracking.max_depth_m <= 20))
      r.fail(t->get("max_depth_m") ? t->get("max_depth_m") : t->get("min_depth_m"),
             "depth range must satisfy 0 < min_depth_m < max_depth_m <= 20");
    if (c.tracking.device != "cpu" && c.tracking.device != "opencl")
      r.fail(t->get("device"), "device '" + c.tracking.device + "' is not \"cpu\" or \"opencl\"");
    if (!(c.tracking.rolling_shutter_readout_s >= 0 && c.tracking.rolling_shutter_readout_s < 0.1))
      r.fail(t->get("rolling_shutter_readout_s"),
             "rolling_shutter_readout_s must be in [0, 0.1) seconds");
  }
  if (auto* t = r.optional_table(root, "world")) {
    r.only(*t, "[world]", {"anchor", "marker", "max_step_mm", "floor_max_tilt_deg"});
    r.get(*t, "anchor", c.world.anchor);
    r.get(*t, "marker", c.world.marker);
    r.get(*t, "max_step_mm", c.world.max_step_mm);
    r.get(*t, "floor_max_tilt_deg", c.world.floor_max_tilt_deg);
    static const std::set<std::string> anchors{"marker", "floor", "rig"};
    if (!anchors.contains(c.world.anchor))
      r.fail(t->get("anchor"),
             "anchor '" + c.world.anchor + "' is not one of \"marker\", \"floor\", \"rig\"");
    try {
      parse_board_spec(c.world.marker);
    } catch (const std::invalid_argument& e) {
      r.fail(t->get("marker"), e.what());
    }
    if (parse_board_spec(c.world.marker).kind == BoardSpec::Kind::Chessboard)
      r.fail(t->get("marker"),
             "a chessboard cannot anchor the world (its pose is ambiguous under rotation by "
             "180 degrees): use a ChArUco board or an ArUco marker");
    if (!(c.world.max_step_mm > 0 && c.world.max_step_mm <= 1000))
      r.fail(t->get("max_step_mm"), "max_step_mm must be in (0, 1000]");
    if (!(c.world.floor_max_tilt_deg > 0 && c.world.floor_max_tilt_deg < 90))
      r.fail(t->get("floor_max_tilt_deg"), "floor_max_tilt_deg must be in (0, 90)");
  }
  if (auto* t = r.optional_table(root, "http")) {
    r.only(*t, "[http]",
           {"enabled", "address", "port", "jpeg_quality", "allowed_hosts", "auth", "user",
            "password", "token", "cors_origin", "max_streams_per_peer", "max_connections",
            "max_stream_clients", "header_timeout_s", "stalled_client_timeout_s"});
    r.get(*t, "enabled", c.http.enabled);
    r.get(*t, "address", c.http.address);
    r.get(*t, "port", c.http.port);
    r.get(*t, "jpeg_quality", c.http.jpeg_quality);
    if (c.http.port < 0 || c.http.port > 65535) r.fail(t->get("port"), "port out of range");
    if (c.http.jpeg_quality < 1 || c.http.jpeg_quality > 100)
      r.fail(t->get("jpeg_quality"), "jpeg_quality must be 1..100");
    parse_http_access(r, *t, c.http.access);
    double header_s = static_cast<double>(c.http.header_timeout.count()) / 1000;
    int stalled_s = static_cast<int>(c.http.stalled_client_timeout.count());
    r.get(*t, "max_connections", c.http.max_connections);
    r.get(*t, "max_stream_clients", c.http.max_stream_clients);
    if (c.http.max_stream_clients < 1 || c.http.max_stream_clients > 4096)
      r.fail(t->get("max_stream_clients"), "max_stream_clients must be 1..4096");
    r.get(*t, "header_timeout_s", header_s);
    r.get(*t, "stalled_client_timeout_s", stalled_s);
    if (c.http.max_connections < 1 || c.http.max_connections > 65536)
      r.fail(t->get("max_connections"), "max_connections must be 1..65536");
    if (!(header_s >= 0.1 && header_s <= 600))
      r.fail(t->get("header_timeout_s"), "header_timeout_s must be 0.1..600");
    if (stalled_s < 1 || stalled_s > 3600)
      r.fail(t->get("stalled_client_timeout_s"), "stalled_client_timeout_s must be 1..3600");
    c.http.header_timeout = std::chrono::milliseconds(std::lround(header_s * 1000));
    c.http.stalled_client_timeout = std::chrono::seconds(stalled_s);
  }
  if (auto* t = r.optional_table(root, "rtsp")) {
    r.only(*t, "[rtsp]",
           {"enabled", "address", "port", "path", "bitrate_kbps", "keyframe_interval", "framerate",
            "encoder", "user", "password", "max_sessions"});
    r.get(*t, "user", c.rtsp.user);
    r.get(*t, "password", c.rtsp.password);
    r.get(*t, "max_sessions", c.rtsp.max_sessions);
    if (c.rtsp.user.empty() != c.rtsp.password.empty())
      r.fail(t->get(c.rtsp.user.empty() ? "password" : "user"),
             "user and password go together (RTSP basic authentication)");
    if (c.rtsp.max_sessions < 0)
      r.fail(t->get("max_sessions"), "max_sessions must be >= 0 (0: no cap)");
    r.get(*t, "enabled", c.rtsp.enabled);
    r.get(*t, "address", c.rtsp.address);
    r.get(*t, "port", c.rtsp.port);
    r.get(*t, "path", c.rtsp.path);
    r.get(*t, "bitrate_kbps", c.rtsp.bitrate_kbps);
    r.get(*t, "keyframe_interval", c.rtsp.keyframe_interval);
    r.get(*t, "framerate", c.rtsp.framerate);
    r.get(*t, "encoder", c.rtsp.encoder);
    if (c.rtsp.port < 0 || c.rtsp.port > 65535) r.fail(t->get("port"), "port out of range");
    try {
      check_rtsp_path(c.rtsp.path);
    } catch (const RtspServerError& e) {
      r.fail(t->get("path"), e.what());
    }
    if (c.rtsp.bitrate_kbps < 64 || c.rtsp.bitrate_kbps > 100000)
      r.fail(t->get("bitrate_kbps"), "bitrate_kbps must be in 64..100000");
    if (c.rtsp.keyframe_interval < 1 || c.rtsp.keyframe_interval > 600)
      r.fail(t->get("keyframe_interval"), "keyframe_interval must be in 1..600 frames");
    if (c.rtsp.framerate < 1 || c.rtsp.framerate > 240)
      r.fail(t->get("framerate"), "framerate must be in 1..240");
    static const std::set<std::string> encoders{"auto", "v4l2h264enc", "x264enc"};
    if (!encoders.contains(c.rtsp.encoder))
      r.fail(t->get("encoder"), "encoder must be \"auto\", \"v4l2h264enc\" or \"x264enc\"");
  }
  if (auto* t = r.optional_table(root, "webrtc")) parse_webrtc(r, *t, c.webrtc);
  if (auto* t = r.optional_table(root, "output")) {
    r.only(*t, "[output]", {"dir", "format", "matte", "max_mb", "keep_minutes", "when_full"});
    std::string dir = c.files.dir.string();
    std::string format = c.files.format == ImageFileFormat::Png ? "png" : "jpeg";
    std::string when_full = c.files.stop_when_full ? "stop" : "remove-oldest";
    int max_mb = static_cast<int>(c.files.max_bytes / 1'000'000);
    int keep_minutes = static_cast<int>(c.files.max_age.count());
    r.get(*t, "dir", dir);
    r.get(*t, "format", format);
    r.get(*t, "matte", c.files.write_matte);
    r.get(*t, "max_mb", max_mb);
    r.get(*t, "keep_minutes", keep_minutes);
    r.get(*t, "when_full", when_full);
    if (format != "jpeg" && format != "png")
      r.fail(t->get("format"), "format must be \"jpeg\" or \"png\"");
    if (max_mb < 0) r.fail(t->get("max_mb"), "max_mb must be >= 0 (0: no size cap)");
    // A year: a longer age cap is no cap, and minutes past it overflow file times.
    if (keep_minutes < 0 || keep_minutes > 525'600)
      r.fail(t->get("keep_minutes"), "keep_minutes must be in 0..525600 (0: no age cap)");
    if (when_full != "remove-oldest" && when_full != "stop")
      r.fail(t->get("when_full"), "when_full must be \"remove-oldest\" or \"stop\"");
    c.files.max_bytes = static_cast<std::uint64_t>(max_mb) * 1'000'000;
    c.files.max_age = std::chrono::minutes(keep_minutes);
    c.files.stop_when_full = when_full == "stop";
    c.files.dir = dir;
    c.files.format = parse_image_file_format(format);
  }
  if (auto* t = r.optional_table(root, "opencl")) {
    r.only(*t, "[opencl]", {"platform", "device"});
    r.get(*t, "platform", c.cl_platform);
    r.get(*t, "device", c.cl_device);
  }
  if (auto* t = r.optional_table(root, "bracket")) {
    r.only(*t, "[bracket]",
           {"enabled", "mains_hz", "max_gain_db", "initial_exposure_ms", "gpio_chip", "gpio_line",
            "strobe_chip", "strobe_line", "strobe_edge"});
    r.get(*t, "enabled", c.bracket_enabled);
    r.get(*t, "mains_hz", c.bracket.mains_hz);
    r.get(*t, "max_gain_db", c.bracket.max_gain_db);
    double initial_ms = c.bracket.initial_exposure * 1e3;
    r.get(*t, "initial_exposure_ms", initial_ms);
    c.bracket.initial_exposure = initial_ms * 1e-3;
    r.get(*t, "gpio_chip", c.trigger_chip);
    r.get(*t, "gpio_line", c.trigger_line);
    r.get(*t, "strobe_chip", c.strobe_chip);
    r.get(*t, "strobe_line", c.strobe_line);
    r.get(*t, "strobe_edge", c.strobe_edge);
    if (c.bracket.mains_hz < 0) r.fail(t->get("mains_hz"), "mains_hz must be >= 0 (0: no limit)");
    if (c.bracket.max_gain_db < 0) r.fail(t->get("max_gain_db"), "max_gain_db must be >= 0");
    if (!(initial_ms > 0)) r.fail(t->get("initial_exposure_ms"), "must be positive");
    if (c.trigger_line < 0) r.fail(t->get("gpio_line"), "gpio_line must be >= 0");
    if (c.strobe_line < 0) r.fail(t->get("strobe_line"), "strobe_line must be >= 0");
    try {
      parse_strobe_edge(c.strobe_edge);
    } catch (const std::invalid_argument& e) {
      r.fail(t->get("strobe_edge"), e.what());
    }
  }
  if (auto* t = r.optional_table(root, "ground")) {
    r.only(*t, "[ground]", {"enabled", "height_m", "size_m", "albedo"});
    r.get(*t, "enabled", c.ground.enabled);
    if (t->get("height_m")) {
      double h = 0;
      r.get(*t, "height_m", h);
      c.ground.height_m = h;
    }
    r.get(*t, "size_m", c.ground.size_m);
    r.get_vector<3>(*t, "albedo", c.ground.albedo);
    if (!(c.ground.size_m > 0 && c.ground.size_m <= 20))
      r.fail(t->get("size_m"), "size_m must be in (0, 20]");
    for (int i = 0; i < 3; ++i)
      if (!(c.ground.albedo[i] >= 0 && c.ground.albedo[i] <= 1))
        r.fail(t->get("albedo"), "albedo must be in [0, 1] per channel");
  }
  if (auto* t = r.optional_table(root, "light")) {
    r.only(*t, "[light]",
           {"enabled", "face_size", "keyframe_distance_m", "max_keyframes", "room", "room_min",
            "room_max", "colour_fill", "update_hz"});
    r.get(*t, "enabled", c.light_enabled);
    r.get(*t, "face_size", c.light_face_size);
    r.get(*t, "keyframe_distance_m", c.light_keyframe_distance_m);
    r.get(*t, "max_keyframes", c.light_max_keyframes);
    r.get(*t, "room", c.light_room);
    r.get(*t, "colour_fill", c.light_colour_fill);
    r.get(*t, "update_hz", c.light_update_hz);
    if (!(c.light_update_hz == 0 || (c.light_update_hz >= 1 && c.light_update_hz <= 1000)))
      r.fail(t->get("update_hz"), "update_hz must be 0 (every frame) or in 1..1000");
    r.get_vector<3>(*t, "room_min", c.light_room_min);
    r.get_vector<3>(*t, "room_max", c.light_room_max);
    if (c.light_room != "off" && c.light_room != "auto" && c.light_room != "sim" &&
        c.light_room != "box")
      r.fail(t->get("room"), "room must be \"off\", \"auto\", \"sim\" or \"box\"");
    const bool has_box = t->get("room_min") || t->get("room_max");
    if (c.light_room == "box") {
      if (!t->get("room_min") || !t->get("room_max"))
        r.fail(t->get("room"), "room = \"box\" needs room_min and room_max");
      if (!(c.light_room_min.array() < c.light_room_max.array()).all())
        r.fail(t->get("room_max"), "room_max must be above room_min in x, y and z");
    } else if (has_box) {
      r.fail(t->get("room_min") ? t->get("room_min") : t->get("room_max"),
             "room_min and room_max are used with room = \"box\"");
    }
    // Multiples of 32: the renderer's SH come from the keyframe box-averaged to 32 px faces.
    if (c.light_face_size < 32 || c.light_face_size > 1024 || c.light_face_size % 32 != 0)
      r.fail(t->get("face_size"), "face_size must be a multiple of 32 in 32..1024");
    if (!(c.light_keyframe_distance_m > 0))
      r.fail(t->get("keyframe_distance_m"), "keyframe_distance_m must be positive");
    // Past 256 keyframes the cap is no budget: 3.8 GB at 192 px faces.
    if (c.light_max_keyframes < 1 || c.light_max_keyframes > 256)
      r.fail(t->get("max_keyframes"), "max_keyframes must be in 1..256");
  }
  if (auto* t = r.optional_table(root, "display")) {
    r.only(*t, "[display]", {"enabled", "card", "connector", "mode"});
    r.get(*t, "enabled", c.display.enabled);
    r.get(*t, "card", c.display.screen.card);
    r.get(*t, "connector", c.display.screen.connector);
    r.get(*t, "mode", c.display.screen.mode);
    if (!c.display.screen.mode.empty()) {
      try {
        display::parse_mode_request(c.display.screen.mode);
      } catch (const display::DisplayError& e) {
        r.fail(t->get("mode"), e.what());
      }
    }
  }
  if (auto* t = r.optional_table(root, "pipeline")) {
    r.only(*t, "[pipeline]", {"frames", "no_signal_after_ms"});
    r.get(*t, "frames", c.max_frames);
    r.get(*t, "no_signal_after_ms", c.no_signal_after_ms);
    if (c.no_signal_after_ms <= 0) r.fail(t->get("no_signal_after_ms"), "must be positive");
  }
  return c;
}

// One file's table, its [[object]] model paths made absolute: they are relative to the
// file that names them, which a board file merged under a config is not.
toml::table read_config_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ParseError(path, 0, "cannot open the configuration file");
  std::stringstream ss;
  ss << in.rdbuf();
  toml::table root = TomlReader{path}.parse(ss.str());
  const auto dir = std::filesystem::path(path).parent_path();
  if (toml::array* objects = root["object"].as_array())
    for (auto& item : *objects)
      if (toml::table* o = item.as_table())
        if (auto model = (*o)["model"].value<std::string>();
            model && !model->empty() && std::filesystem::path(*model).is_relative())
          o->insert_or_assign("model", (dir / *model).string());
  return root;
}

}  // namespace

ServiceConfig parse_service_config(std::string_view text, std::string_view source_name) {
  const TomlReader r{std::string(source_name)};
  return parse_service_table(r, r.parse(text));
}

ServiceConfig load_service_config(const std::string& path, const std::string& board) {
  toml::table root;
  if (!path.empty()) root = read_config_table(path);
  const TomlReader r{path.empty() ? std::string("--board") : path};
  std::string board_ref = board;
  std::filesystem::path relative_to = std::filesystem::current_path();
  if (board_ref.empty() && root.get("board")) {
    r.get(root, "board", board_ref);
    relative_to = std::filesystem::path(path).parent_path();
  }
  if (!board_ref.empty()) {
    std::filesystem::path board_path;
    try {
      board_path = find_board_file(board_ref, relative_to);
    } catch (const std::runtime_error& e) {
      r.fail(board.empty() ? root.get("board") : nullptr, e.what());
    }
    toml::table merged = read_config_table(board_path.string());
    if (merged.get("board"))
      TomlReader{board_path.string()}.fail(merged.get("board"),
                                           "a board file cannot name another board");
    root.erase("board");
    merge_toml(merged, std::move(root));
    root = std::move(merged);
    root.insert_or_assign("board", board_path.string());
  }
  return parse_service_table(r, root);
}

}  // namespace probeless

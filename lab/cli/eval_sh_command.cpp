// probeless eval sh: spherical-harmonic coefficients of a lat-long HDR probe, 5 bands (25 per
// channel) and the 9 of the first 3 that R&H's irradiance formula uses (docs/lighting.md
// "probeless eval sh"; core/sh.hpp).
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/sh.hpp"
#include "drivers/io/hdr_image.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string probe;
  std::string json;
  double scale = 1.0;
  std::string convention = "z-up";
};

constexpr const char* kZUp =
    "z-up: probeless's world frame (right-handed, z up). The lat-long map's row 0 is the "
    "zenith (+z), its centre column looks along -y, three quarters across along +x, the left "
    "and right edges along +y (the USC ICT probe layout; core/latlong.hpp). Real SH, "
    "orthonormal, R&H signs (no Condon-Shortley phase): L1-1 ~ y, L10 ~ z, L11 ~ x. Index "
    "l(l+1)+m.";
constexpr const char* kYUp =
    "y-up: the frame of Ramamoorthi & Hanrahan's published tables (Orange Book; "
    "../shared/data/sh-reference): x = y_world, y = z_world (up), z = x_world, i.e. for lat-long "
    "pixel (row, col): theta = (row+0.5)/H pi, phi = (col+0.5)/W 2pi, direction = (sin theta "
    "cos phi, cos theta, -sin theta sin phi). Real SH, orthonormal, R&H signs (no "
    "Condon-Shortley phase): L1-1 ~ y, L10 ~ z, L11 ~ x. Index l(l+1)+m.";

std::string coefficient_name(int i) {
  const int l = static_cast<int>(std::sqrt(static_cast<double>(i)));
  return fmt::format("L{}{}", l, i - l * (l + 1));  // L1-1, L10, L11, ...
}

void run(const Options& o) {
  if (!(std::isfinite(o.scale) && o.scale > 0.0))
    throw CommandError(fmt::format("--scale must be finite and > 0 (got {})", o.scale));
  ImageRGBF probe;
  try {
    probe = read_hdr_image(o.probe);
  } catch (const std::exception& e) {
    throw CommandError(e.what());
  }
  if (probe.empty() || probe.width() != 2 * probe.height())
    throw CommandError(
        fmt::format("{}: {}x{} is not a latitude-longitude map (width must be "
                    "twice the height)",
                    o.probe, probe.width(), probe.height()));
  for (float& v : probe.elements()) {
    if (!std::isfinite(v)) throw CommandError(o.probe + ": contains non-finite values");
    v = static_cast<float>(v * o.scale);
  }
  ShRgb sh = project_sh_latlong(probe, kShMaxBands);
  if (o.convention == "y-up") {
    Eigen::Matrix3d world_to_yup;  // rows: x_yup = y, y_yup = z, z_yup = x (a rotation)
    world_to_yup << 0, 1, 0, 0, 0, 1, 1, 0, 0;
    sh = rotate_sh(sh, world_to_yup);
  }

  std::cout << fmt::format("{} ({}x{}, scale {}), convention {}\n", o.probe, probe.width(),
                           probe.height(), o.scale, o.convention);
  nlohmann::json sh9 = nlohmann::json::array(), sh25 = nlohmann::json::array();
  for (int i = 0; i < kShMaxCount; ++i) {
    const Eigen::Vector3d& c = sh.c[static_cast<std::size_t>(i)];
    std::cout << fmt::format("{:>3} {:<5} {:>12.7f} {:>12.7f} {:>12.7f}{}\n", i,
                             coefficient_name(i), c[0], c[1], c[2], i < 9 ? "  (sh9)" : "");
    const nlohmann::json rgb = {c[0], c[1], c[2]};
    sh25.push_back(rgb);
    if (i < 9) sh9.push_back(rgb);
  }
  if (!o.json.empty()) {
    nlohmann::json names = nlohmann::json::array();
    for (int i = 0; i < kShMaxCount; ++i) names.push_back(coefficient_name(i));
    const nlohmann::json j = {{"probe", o.probe},
                              {"width", probe.width()},
                              {"height", probe.height()},
                              {"scale", o.scale},
                              {"convention", o.convention == "y-up" ? kYUp : kZUp},
                              {"names", names},
                              {"sh9", sh9},
                              {"sh25", sh25}};
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_eval_sh_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "sh", "Spherical-harmonic coefficients (9 and 25 per channel) of a lat-long HDR probe");
  cmd->add_option("--probe", o->probe, "Lat-long (2:1) Radiance .hdr or OpenEXR .exr")->required();
  cmd->add_option("--json", o->json, "Write {sh9, sh25, convention, ...} as JSON");
  cmd->add_option("--scale", o->scale, "Multiply the radiance by this first")
      ->capture_default_str();
  cmd->add_option("--convention", o->convention,
                  "Axes: z-up (probeless world) or y-up (R&H / Orange Book tables)")
      ->check(CLI::IsMember({"z-up", "y-up"}))
      ->capture_default_str();
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli

#include "core/calibration.hpp"

#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/ocam.hpp"
#include "core/error.hpp"
#include "core/toml_reader.hpp"

namespace probeless {
namespace {

PinholeCamera read_rgb(const TomlReader& r, const toml::table& root) {
  const toml::table& t = r.table(root, "the top level", "rgb");
  r.only(t, "[rgb]", {"width", "height", "fx", "fy", "cx", "cy", "distortion"});
  PinholeIntrinsics k;
  std::tie(k.width, k.height) = r.image_size(t, "[rgb]");
  k.fx = r.number(t, "[rgb]", "fx");
  k.fy = r.number(t, "[rgb]", "fy");
  k.cx = r.number(t, "[rgb]", "cx");
  k.cy = r.number(t, "[rgb]", "cy");
  if (!(k.fx > 0)) r.fail(t.get("fx"), "fx must be positive");
  if (!(k.fy > 0)) r.fail(t.get("fy"), "fy must be positive");
  BrownDistortion d;
  if (t.contains("distortion")) {
    // Any coefficient left out is zero: many calibrations give only k1 and k2.
    const toml::table& dt = r.table(t, "[rgb]", "distortion");
    r.only(dt, "[rgb.distortion]", {"k1", "k2", "p1", "p2", "k3"});
    d.k1 = r.number_or(dt, "k1", 0);
    d.k2 = r.number_or(dt, "k2", 0);
    d.p1 = r.number_or(dt, "p1", 0);
    d.p2 = r.number_or(dt, "p2", 0);
    d.k3 = r.number_or(dt, "k3", 0);
  }
  return PinholeCamera(k, d);
}

std::shared_ptr<const CameraModel> read_kannala_brandt(const TomlReader& r, const toml::table& t) {
  const std::string where = "[fisheye] (kannala_brandt)";
  r.only(t, where, {"model", "width", "height", "fx", "fy", "cx", "cy", "k", "max_theta"});
  KannalaBrandtParams p;
  std::tie(p.width, p.height) = r.image_size(t, where);
  p.fx = r.number(t, where, "fx");
  p.fy = r.number(t, where, "fy");
  p.cx = r.number(t, where, "cx");
  p.cy = r.number(t, where, "cy");
  if (t.contains("k")) {
    const auto k = r.numbers(t, where, "k", 4, 4);
    std::copy(k.begin(), k.end(), p.k.begin());
  }
  p.max_theta = r.number_or(t, "max_theta", p.max_theta);
  try {
    return std::make_shared<KannalaBrandtCamera>(p);
  } catch (const std::invalid_argument& e) {
    r.fail(&t, e.what());
  }
}

std::shared_ptr<const CameraModel> read_ocam(const TomlReader& r, const toml::table& t,
                                             std::string& file) {
  const std::string where = "[fisheye] (ocam)";
  if (const toml::node* f = t.get("file")) {
    r.only(t, where + " with a file", {"model", "file"});
    if (!f->is_string() || f->as_string()->get().empty())
      r.fail(f, "file: expected the path of an OCamCalib calib_results.txt");
    file = f->as_string()->get();
    return nullptr;
  }
  r.only(t, where,
         {"model", "file", "width", "height", "pol", "invpol", "xc", "yc", "c", "d", "e"});
  OCamParams p;
  std::tie(p.width, p.height) = r.image_size(t, where);
  p.pol = r.numbers(t, where, "pol", 1, 64);
  p.invpol = r.numbers(t, where, "invpol", 1, 64);
  p.xc = r.number(t, where, "xc");
  p.yc = r.number(t, where, "yc");
  p.c = r.number_or(t, "c", 1);
  p.d = r.number_or(t, "d", 0);
  p.e = r.number_or(t, "e", 0);
  try {
    return std::make_shared<OCamCamera>(std::move(p));
  } catch (const std::invalid_argument& e) {
    r.fail(&t, e.what());
  }
}

Pose read_pose(const TomlReader& r, const toml::table& extrinsics, std::string_view key) {
  const std::string where = "[extrinsics] " + std::string(key);
  const toml::node& node = r.require(extrinsics, "[extrinsics]", key);
  if (!node.is_table())
    r.fail(&node, std::string(key) +
                      ": expected {translation = [x, y, z], rotation_xyzw = "
                      "[x, y, z, w]}");
  const toml::table& t = *node.as_table();
  r.only(t, where, {"translation", "rotation_xyzw"});
  const auto tr = r.numbers(t, where, "translation", 3, 3);
  const auto q = r.numbers(t, where, "rotation_xyzw", 4, 4);
  Pose pose;
  pose.translation = {tr[0], tr[1], tr[2]};
  pose.rotation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
  // Hand-typed values with a few digits are normalised; anything far from unit length is a
  // mistake. Values to_toml wrote (17 digits) are kept bit for bit.
  const double norm_error = std::abs(pose.rotation.norm() - 1.0);
  if (norm_error > 1e-6) r.fail(t.get("rotation_xyzw"), "rotation_xyzw: not a unit quaternion");
  if (norm_error > 1e-12) pose.rotation.normalize();
  return pose;
}

// Shortest text that reads back as the same double, always in TOML float syntax.
std::string number_text(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, res.ptr);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "n": inf and nan
  return s;
}

std::string array_text(const double* v, std::size_t n) {
  std::string s = "[";
  for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + number_text(v[i]);
  return s + "]";
}

std::string pose_text(const Pose& p) {
  const Eigen::Quaterniond& q = p.rotation;
  const double xyzw[4] = {q.x(), q.y(), q.z(), q.w()};
  return "{translation = " + array_text(p.translation.data(), 3) +
         ", rotation_xyzw = " + array_text(xyzw, 4) + "}";
}

// The body of the [fisheye] table: a file reference, or the model's parameters inline.
std::string fisheye_table(const RigCalibration& c) {
  std::ostringstream out;
  if (!c.fisheye_file.empty()) {
    out << "model = \"ocam\"\nfile = " << toml::value<std::string>(c.fisheye_file) << "\n";
  } else if (const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(c.fisheye.get())) {
    const KannalaBrandtParams& p = kb->params();
    out << "model = \"kannala_brandt\"\n"
        << "width = " << p.width << "\nheight = " << p.height << "\n"
        << "fx = " << number_text(p.fx) << "\nfy = " << number_text(p.fy) << "\n"
        << "cx = " << number_text(p.cx) << "\ncy = " << number_text(p.cy) << "\n"
        << "k = " << array_text(p.k.data(), p.k.size()) << "\n"
        << "max_theta = " << number_text(p.max_theta) << "\n";
  } else if (const auto* oc = dynamic_cast<const OCamCamera*>(c.fisheye.get())) {
    const OCamParams& p = oc->params();
    out << "model = \"ocam\"\n"
        << "width = " << p.width << "\nheight = " << p.height << "\n"
        << "pol = " << array_text(p.pol.data(), p.pol.size()) << "\n"
        << "invpol = " << array_text(p.invpol.data(), p.invpol.size()) << "\n"
        << "xc = " << number_text(p.xc) << "  # row\nyc = " << number_text(p.yc) << "  # column\n"
        << "c = " << number_text(p.c) << "\nd = " << number_text(p.d)
        << "\ne = " << number_text(p.e) << "\n";
  } else {
    throw std::invalid_argument(
        "to_toml: the fisheye must be a Kannala-Brandt or OCam model, or name a file");
  }
  return out.str();
}

}  // namespace

RigCalibration parse_rig_calibration(std::string_view toml_text, std::string_view source_name) {
  const TomlReader r{std::string(source_name)};
  const toml::table root = r.parse(toml_text);
  r.only(root, "the top level", {"rgb", "fisheye", "extrinsics"});
  RigCalibration c;
  c.rgb = read_rgb(r, root);

  // [fisheye] is optional: an RGB-D-only rig (a TUM sequence, a recording of one) has none,
  // and its fisheye pointer stays null. With the table present, the model is required.
  if (root.contains("fisheye")) {
    const toml::table& fisheye = r.table(root, "the top level", "fisheye");
    const std::string model = r.string(fisheye, "[fisheye]", "model");
    if (model == "kannala_brandt") {
      c.fisheye = read_kannala_brandt(r, fisheye);
    } else if (model == "ocam") {
      c.fisheye = read_ocam(r, fisheye, c.fisheye_file);
    } else {
      r.fail(fisheye.get("model"),
             "model: expected \"kannala_brandt\" or \"ocam\", got \"" + model + "\"");
    }
  }

  const toml::table& ex = r.table(root, "the top level", "extrinsics");
  r.only(ex, "[extrinsics]", {"T_rig_rgb", "T_rig_fisheye", "depth_baseline_m"});
  c.T_rig_rgb = read_pose(r, ex, "T_rig_rgb");
  c.T_rig_fisheye = read_pose(r, ex, "T_rig_fisheye");
  c.depth_baseline_m = r.number_or(ex, "depth_baseline_m", c.depth_baseline_m);
  if (!(c.depth_baseline_m > 0))
    r.fail(ex.get("depth_baseline_m"), "depth_baseline_m must be positive");
  return c;
}

std::string to_toml(const RigCalibration& c) {
  std::ostringstream out;
  const PinholeIntrinsics& k = c.rgb.intrinsics();
  out << "# probeless rig calibration (docs/camera-models.md)\n\n"
      << "[rgb]\n"
      << "width = " << k.width << "\nheight = " << k.height << "\n"
      << "fx = " << number_text(k.fx) << "\nfy = " << number_text(k.fy) << "\n"
      << "cx = " << number_text(k.cx) << "\ncy = " << number_text(k.cy) << "\n";
  if (const BrownDistortion& d = c.rgb.distortion(); !d.is_zero())
    out << "\n[rgb.distortion]\n"
        << "k1 = " << number_text(d.k1) << "\nk2 = " << number_text(d.k2) << "\n"
        << "p1 = " << number_text(d.p1) << "\np2 = " << number_text(d.p2) << "\n"
        << "k3 = " << number_text(d.k3) << "\n";

  // An RGB-D-only rig (no fisheye, no file) has no [fisheye] table; parsing accepts that.
  if (c.fisheye || !c.fisheye_file.empty()) out << "\n[fisheye]\n" << fisheye_table(c);

  out << "\n[extrinsics]\n"
      << "T_rig_rgb = " << pose_text(c.T_rig_rgb) << "\n"
      << "T_rig_fisheye = " << pose_text(c.T_rig_fisheye) << "\n"
      << "depth_baseline_m = " << number_text(c.depth_baseline_m) << "\n";
  return out.str();
}

}  // namespace probeless

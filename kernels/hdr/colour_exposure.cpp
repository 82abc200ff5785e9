#include "kernels/hdr/colour_exposure.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "kernels/hdr/hdr_conversion_reference.hpp"

namespace probeless {

ColourExposureEstimator::ColourExposureEstimator(const PinholeCamera& rgb,
                                                 std::shared_ptr<const CameraModel> fisheye,
                                                 const Pose& T_rig_rgb, const Pose& T_rig_fisheye,
                                                 ColourExposureParams params)
    : rgb_(rgb),
      fisheye_(std::move(fisheye)),
      T_fisheye_rgb_(T_rig_fisheye.inverse() * T_rig_rgb),
      params_(params) {
  const auto& p = params_;
  if (!fisheye_) throw std::invalid_argument("colour exposure: no fisheye camera model");
  if (p.stride < 1) throw std::invalid_argument("colour exposure: stride must be >= 1");
  if (!(p.top_fraction > 0.0 && p.top_fraction <= 1.0))
    throw std::invalid_argument("colour exposure: top_fraction must be in (0, 1]");
  if (p.min_matches < 1) throw std::invalid_argument("colour exposure: min_matches must be >= 1");
  if (!(p.gamma > 0.0 && std::isfinite(p.gamma)))
    throw std::invalid_argument("colour exposure: gamma must be > 0");
  if (!(p.colour_black >= 0 && p.colour_black < p.colour_saturated && p.colour_saturated <= 255))
    throw std::invalid_argument(
        "colour exposure: need 0 <= colour_black < colour_saturated <= 255");
  validate(p.fisheye);
  for (int v = 0; v < 256; ++v)
    inverse_gamma_[v] = static_cast<float>(std::pow(v / 255.0, p.gamma));
}

bool ColourExposureEstimator::update(const RgbdFrame& rgbd, const FisheyeFrame& fisheye) {
  const ImageRGB8& colour = rgbd.colour;
  const DepthImage& depth = rgbd.depth;
  if (colour.width() != depth.width() || colour.height() != depth.height())
    throw std::invalid_argument("colour exposure: colour and depth sizes differ");
  if (colour.width() != rgb_.width() || colour.height() != rgb_.height())
    throw std::invalid_argument("colour exposure: colour frame " + std::to_string(colour.width()) +
                                "x" + std::to_string(colour.height()) +
                                " is not the colour camera's " + std::to_string(rgb_.width()) +
                                "x" + std::to_string(rgb_.height()));
  const ImageRGB16& raw = fisheye.raw;
  if (raw.width() != fisheye_->width() || raw.height() != fisheye_->height())
    throw std::invalid_argument(
        "colour exposure: fisheye frame " + std::to_string(raw.width()) + "x" +
        std::to_string(raw.height()) + " is not the fisheye camera's " +
        std::to_string(fisheye_->width()) + "x" + std::to_string(fisheye_->height()));
  const HdrConversionConstants c = hdr_conversion_constants(
      fisheye.bit_depth, fisheye.black_level, fisheye.exposure.exposure, params_.fisheye);

  const int rows = std::clamp(static_cast<int>(std::ceil(params_.top_fraction * colour.height())),
                              0, colour.height());
  Eigen::Vector3d sum_f = Eigen::Vector3d::Zero(), sum_l = Eigen::Vector3d::Zero();
  int matches = 0;
  // Offset by half a stride so the grid sits inside the image, not on its border.
  for (int y = params_.stride / 2; y < rows; y += params_.stride) {
    for (int x = params_.stride / 2; x < colour.width(); x += params_.stride) {
      const std::uint16_t z_mm = depth.at(x, y);
      if (z_mm == 0) continue;  // no depth
      const std::uint8_t* rgb8 = &colour.at(x, y, 0);
      const int hi = std::max({rgb8[0], rgb8[1], rgb8[2]});
      if (hi >= params_.colour_saturated || hi <= params_.colour_black) continue;
      const auto ray = rgb_.unproject(Eigen::Vector2d(x, y));
      if (!ray || !(ray->z() > 0.0)) continue;
      const Eigen::Vector3d p_rgb = *ray * (z_mm * 1e-3 / ray->z());  // depth is along z
      const auto px = fisheye_->project(T_fisheye_rgb_ * p_rgb);
      if (!px || !fisheye_->in_image(*px)) continue;
      const int u = static_cast<int>(std::lround(px->x()));
      const int v = static_cast<int>(std::lround(px->y()));
      const auto f = hdr_convert_pixel(&raw.at(u, v, 0), u, v, fisheye.black_level, c);
      if (!(f[3] > 0.0f)) continue;  // saturated, black or outside the image circle
      for (int ch = 0; ch < 3; ++ch) {
        sum_f[ch] += f[ch];
        sum_l[ch] += inverse_gamma_[rgb8[ch]];
      }
      ++matches;
    }
  }
  estimate_.matches = matches;
  if (matches < params_.min_matches || !(sum_l.minCoeff() > 0.0)) return false;
  estimate_.e = sum_f.cwiseQuotient(sum_l);
  estimate_.valid = true;
  return true;
}

}  // namespace probeless

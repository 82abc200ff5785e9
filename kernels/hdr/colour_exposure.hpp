#pragma once
// The RGB-D colour camera's exposure and white balance relative to the fisheye (thesis ch. 5;
// issue #5 deliver 2; docs/lighting.md "Colour camera exposure"). The colour camera runs its
// own auto-exposure and white balance; to put its pixels into the light model's units we
// need per channel e with  fisheye radiance = e * colour linear. Over pixels both cameras see:
//   e_c = sum(f_c) / sum(l_c),   l = (8-bit colour / 255)^2.2 (inverse gamma),
// f the fisheye's HDR conversion at the point the colour pixel's depth puts in the fisheye
// (rig calibration T_rig_rgb, T_rig_fisheye and the fisheye camera model). Sparse: a grid of
// samples over the top of the colour image (the part an upward fisheye shares with it), so
// plain CPU code; the fisheye samples go through the HDR conversion's reference per pixel,
// from the raw frame on the host, with the same flags as the kernel.
#include <Eigen/Core>
#include <cstdint>
#include <memory>

#include "core/camera/camera_model.hpp"
#include "core/camera/pinhole.hpp"
#include "core/frame.hpp"
#include "core/pose.hpp"
#include "kernels/hdr/hdr_conversion.hpp"

namespace probeless {

struct ColourExposureParams {
  int stride = 8;               // one sample every stride pixels in x and y
  double top_fraction = 0.5;    // rows [0, top_fraction * height) of the colour image
  int min_matches = 100;        // fewer matched samples: keep the previous estimate
  int colour_saturated = 250;   // 8-bit: any channel >= this -> saturated (linear 0.96)
  int colour_black = 2;         // 8-bit: all channels <= this -> black
  double gamma = 2.2;           // the colour camera's encoding
  HdrConversionParams fisheye;  // flags (saturated, black, image circle) of fisheye samples
};

struct ColourExposureEstimate {
  Eigen::Vector3d e = Eigen::Vector3d::Ones();  // fisheye radiance per unit colour linear
  bool valid = false;                           // false until a frame had enough matches
  int matches = 0;  // matched samples of the last update (whether or not it was used)
};

class ColourExposureEstimator {
 public:
  // Throws std::invalid_argument for a null fisheye model or bad params (stride < 1,
  // top_fraction outside (0, 1], min_matches < 1, gamma <= 0, colour limits not 0 <= black <
  // saturated <= 255, or fisheye params as HdrConversionParams' validate).
  ColourExposureEstimator(const PinholeCamera& rgb, std::shared_ptr<const CameraModel> fisheye,
                          const Pose& T_rig_rgb, const Pose& T_rig_fisheye,
                          ColourExposureParams params = {});

  // One colour frame (colour + registered depth, mm) against a fisheye frame taken at about
  // the same time (both are placed in the rig frame; rig motion between them is ignored).
  // Returns true when the estimate was replaced; with fewer than min_matches samples whose
  // colour and fisheye values are both usable it keeps the previous one.
  // Throws std::invalid_argument when colour and depth sizes differ, or either frame's size
  // is not its camera model's, or the fisheye frame's bit depth / black level / exposure is
  // bad.
  bool update(const RgbdFrame& rgbd, const FisheyeFrame& fisheye);

  const ColourExposureEstimate& estimate() const { return estimate_; }
  const ColourExposureParams& params() const { return params_; }

 private:
  PinholeCamera rgb_;
  std::shared_ptr<const CameraModel> fisheye_;
  Pose T_fisheye_rgb_;
  ColourExposureParams params_;
  float inverse_gamma_[256];  // 8-bit colour -> linear
  ColourExposureEstimate estimate_;
};

}  // namespace probeless

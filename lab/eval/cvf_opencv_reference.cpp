#include "lab/eval/cvf_opencv_reference.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_filter.hpp>
#include <vector>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"

namespace probeless::eval {
using namespace probeless::occlusion;

namespace {

// Categories (eroded) and the band around the process region, by cv::dilate.
struct CvCategories {
  cv::Mat cat, band;
};

CvCategories opencv_categories(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                               const CvfParams& p) {
  const int w = real_depth_mm.width(), h = real_depth_mm.height();
  const int n = w * h;
  cv::Mat cat(h, w, CV_8U), infront(h, w, CV_8U), behind(h, w, CV_8U), process(h, w, CV_8U);
  for (int i = 0; i < n; ++i) {
    const auto c = raw_category(real_depth_mm.data()[i], virtual_depth_mm.data()[i], p.categorise);
    cat.data[i] = static_cast<std::uint8_t>(c);
    infront.data[i] = c == Category::Infront ? 255 : 0;
    behind.data[i] = c == Category::Behind ? 255 : 0;
    process.data[i] = c == Category::Process ? 255 : 0;
  }
  if (p.categorise.erosion_px > 0) {
    const auto k = cv::getStructuringElement(
        cv::MORPH_RECT, {2 * p.categorise.erosion_px + 1, 2 * p.categorise.erosion_px + 1});
    cv::Mat near_in, near_be;
    cv::dilate(infront, near_in, k);
    cv::dilate(behind, near_be, k);
    for (int i = 0; i < n; ++i) {
      const auto c = static_cast<Category>(cat.data[i]);
      if ((c == Category::Infront && near_be.data[i]) ||
          (c == Category::Behind && near_in.data[i])) {
        cat.data[i] = static_cast<std::uint8_t>(Category::Process);
        process.data[i] = 255;
      }
    }
  }
  cv::Mat band;
  cv::dilate(process, band,
             cv::getStructuringElement(cv::MORPH_RECT, {2 * p.band_px + 1, 2 * p.band_px + 1}));
  return {cat, band};
}

// The guide goes in as 8-bit with eps scaled to intensities 0..255 (the same filter as
// guide / 255 with eps). With the guide converted to float in [0, 1], OpenCV 4.6's colour
// guided filter departed from the definition on whole regions of the bench frame (24 240
// interior pixels of the wide filter off by > 0.05, up to 1.09; cvf MSE 10.68e-3 instead of
// the exact reference's 7.70e-3); with the 8-bit guide it agrees with guided_filter_reference
// to 5e-7 away from the border (docs/occlusion.md "Speed").
constexpr double kScale2 = 255.0 * 255.0;

// Wide filter, threshold (soft by `softness` where given), feather, alpha.
ImageF filter_and_threshold(const cv::Mat& rgb, const cv::Mat& cat, const cv::Mat& cost,
                            const float* softness, const ImageF& virtual_depth_mm,
                            const CvfParams& p) {
  const int n = rgb.rows * rgb.cols;
  cv::Mat wide, feather;
  cv::ximgproc::guidedFilter(rgb, cost, wide, p.wide.radius, p.wide.eps * kScale2, CV_32F);
  cv::Mat mask(rgb.rows, rgb.cols, CV_32F);
  for (int i = 0; i < n; ++i) {
    const auto c = static_cast<Category>(cat.data[i]);
    const float q = wide.ptr<float>()[i];
    const float hard = q > 0.5F ? 1.0F : 0.0F;
    const float s = softness && c == Category::Process ? softness[i] : 0.0F;
    mask.ptr<float>()[i] = c == Category::Infront ? 1.0F
                           : c == Category::Behind
                               ? 0.0F
                               : (1.0F - s) * hard + s * std::clamp(q, 0.0F, 1.0F);
  }
  cv::ximgproc::guidedFilter(rgb, mask, feather, p.feather.radius, p.feather.eps * kScale2, CV_32F);
  ImageF alpha(rgb.cols, rgb.rows);
  for (int i = 0; i < n; ++i)
    alpha.data()[i] = virtual_depth_mm.data()[i] > 0.0F
                          ? std::clamp(1.0F - feather.ptr<float>()[i], 0.0F, 1.0F)
                          : 0.0F;
  return alpha;
}

}  // namespace

ImageF cvf_opencv_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                            const ImageF& virtual_depth_mm, const CvfParams& p) {
  const int w = colour.width(), h = colour.height();
  const int n = w * h;
  const cv::Mat rgb(h, w, CV_8UC3, const_cast<std::uint8_t*>(colour.data()));
  const auto [cat, band] = opencv_categories(real_depth_mm, virtual_depth_mm, p);
  const int b = p.bins_per_channel;
  ColourModels models{b, std::vector<std::uint32_t>(b * b * b),
                      std::vector<std::uint32_t>(b * b * b)};
  std::vector<int> bins(n);
  for (int i = 0; i < n; ++i) {
    const std::uint8_t* px = colour.data() + 3 * i;
    bins[i] = colour_bin(px[0], px[1], px[2], b);
    const auto c = static_cast<Category>(cat.data[i]);
    if (band.data[i] && (c == Category::Infront || c == Category::Behind))
      (c == Category::Infront ? models.infront : models.behind)[bins[i]]++;
  }
  const auto min_samples = static_cast<std::uint32_t>(std::max(1, p.min_samples));
  const bool valid = models.infront_total() >= min_samples && models.behind_total() >= min_samples;
  cv::Mat cost(h, w, CV_32F);
  for (int i = 0; i < n; ++i)
    cost.ptr<float>()[i] = cvf_cost(static_cast<Category>(cat.data[i]), bins[i], models, valid,
                                    real_depth_mm.data()[i], virtual_depth_mm.data()[i]);
  return filter_and_threshold(rgb, cat, cost, nullptr, virtual_depth_mm, p);
}

ImageF cvf_local_opencv_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                  const ImageF& virtual_depth_mm, const CvfLocalParams& lp) {
  const int w = colour.width(), h = colour.height();
  const cv::Mat rgb(h, w, CV_8UC3, const_cast<std::uint8_t*>(colour.data()));
  const auto [cat, band] = opencv_categories(real_depth_mm, virtual_depth_mm, lp.cvf);
  CategoryImage categories(w, h);
  ImageGray8 band_image(w, h);
  std::copy(cat.data, cat.data + w * h, categories.data());
  std::copy(band.data, band.data + w * h, band_image.data());
  auto costs =
      local_costs_reference(colour, categories, band_image, real_depth_mm, virtual_depth_mm, lp);
  const cv::Mat cost(h, w, CV_32F, costs.cost.data());
  return filter_and_threshold(rgb, cat, cost, costs.softness.data(), virtual_depth_mm, lp.cvf);
}

}  // namespace probeless::eval

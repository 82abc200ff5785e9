#pragma once
// A fisheye's image circle from its images: where the lens's field of view ends inside the
// frame (docs/calibration.md "What it does"), so the fitted model's domain is the lens's and not
// the dark corners'.
#include <vector>

#include "core/image.hpp"

namespace probeless::calib {

// The radius of the image circle in focal lengths ((u - cx) / fx, (v - cy) / fy) from the
// principal point: the first ring, going outwards, whose mean brightness over the images has
// fallen below half way between the inner image's and the outermost ring's, less one pixel.
// 0 when the images have no dark rim (the circle fills the frame) or there are none.
double image_circle_radius(const std::vector<ImageGray8>& images, double fx, double fy, double cx,
                           double cy);

}  // namespace probeless::calib

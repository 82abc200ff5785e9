#pragma once
// The picture of one calibration view for the person to look at (docs/calibration.md): the
// image in gray, each detected corner as a green circle, where the calibrated model puts it
// as a red cross, and the view's RMS in the corner.
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "core/image.hpp"
#include "lab/calib/board_detector.hpp"

namespace probeless::calib {

// Throws std::runtime_error naming the file when it cannot be written.
void write_view_png(const std::filesystem::path& path, const ImageGray8& image,
                    const BoardView& view, const std::vector<Eigen::Vector2d>& reprojected,
                    double rms_px);

}  // namespace probeless::calib

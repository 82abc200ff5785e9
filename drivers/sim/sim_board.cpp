#include "drivers/sim/sim_board.hpp"

#include <array>
#include <cmath>
#include <cstdint>

#include "drivers/sim/sim_rig.hpp"

namespace probeless::sim {
namespace {

// charuco:5x4:80:60:4x4_50: 5 columns and 4 rows of 80 mm squares, 60 mm markers of
// DICT_4X4_50. Large cells (10 mm) so that the board is found from the tabletop view at
// ~1.1 m, where a 640 px camera sees ~2 mm per pixel.
constexpr int kCols = 5, kRows = 4;
constexpr float kSquare = 0.08f, kMarker = 0.06f, kMargin = 0.02f, kThickness = 0.001f;
// DICT_4X4_50's first ten markers, 4x4 bits row-major from the most significant bit, 1 =
// white (cv::aruco::Dictionary::getBitsFromByteList of OpenCV 4.6's bytesList).
constexpr std::array<std::uint16_t, 10> kMarkerBits{0xb532, 0x0f9a, 0x332d, 0x9946, 0x549e,
                                                    0x79cd, 0x9e2e, 0xc4f2, 0xfeda, 0xcf56};
const Eigen::Vector3f kBlack(0.04f, 0.04f, 0.04f), kWhite(0.8f, 0.8f, 0.8f);

// The board's top-left corner as printed, seen from the start of the static and tabletop
// views (looking +y): its image x runs along world +x, its image y along world -y.
Eigen::Vector2f board_top_left() {
  const Eigen::Vector3d a = object_anchor();
  return {static_cast<float>(a.x()) - kCols * kSquare / 2,
          static_cast<float>(a.y()) + kRows * kSquare / 2};
}

}  // namespace

BoardCard board_card() {
  const Eigen::Vector2f tl = board_top_left();
  const float top = static_cast<float>(table_top_height_m());
  return {{tl.x() - kMargin, tl.y() - kRows * kSquare - kMargin, top},
          {tl.x() + kCols * kSquare + kMargin, tl.y() + kMargin, top + kThickness}};
}

Eigen::Vector3f board_albedo(const Eigen::Vector3f& p) {
  const Eigen::Vector2f tl = board_top_left();
  const float bx = p.x() - tl.x(), by = tl.y() - p.y();  // OpenCV's board frame (y down)
  if (bx < 0 || by < 0 || bx >= kCols * kSquare || by >= kRows * kSquare) return kWhite;
  const int sx = static_cast<int>(bx / kSquare), sy = static_cast<int>(by / kSquare);
  // OpenCV 4.6: the first square is black; markers fill the others, ids row by row.
  if ((sx + sy) % 2 == 0) return kBlack;
  int id = 0;
  for (int y = 0; y <= sy; ++y)
    for (int x = 0; x < (y == sy ? sx : kCols); ++x) id += (x + y) % 2;
  const float inset = (kSquare - kMarker) / 2;
  const float u = (bx - sx * kSquare - inset) / kMarker, v = (by - sy * kSquare - inset) / kMarker;
  if (u < 0 || v < 0 || u >= 1 || v >= 1) return kWhite;
  const int cu = static_cast<int>(u * 6), cv = static_cast<int>(v * 6);  // with the border
  if (cu == 0 || cv == 0 || cu == 5 || cv == 5) return kBlack;
  const int bit = (cv - 1) * 4 + (cu - 1);
  return (kMarkerBits[static_cast<std::size_t>(id)] >> (15 - bit)) & 1u ? kWhite : kBlack;
}

}  // namespace probeless::sim

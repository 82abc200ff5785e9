#pragma once
// The ChArUco board on the sim's table (`sim:board=1`; docs/sim.md "The board"): ground truth
// for world anchoring with a marker (issue #17). Drawn here from the dictionary's bits, as
// OpenCV 4.6's CharucoBoard::draw lays it out, since drivers do not link OpenCV; app/world's
// detector finding it at its known pose is the test that the two agree.
#include <Eigen/Core>

namespace probeless::sim {

// The printed card: the board and a white margin, lying face up on the table top.
struct BoardCard {
  Eigen::Vector3f lo, hi;  // world box of the card (1 mm thick)
};
BoardCard board_card();

// Albedo of the card's top face at world point p (black squares and marker cells ~0.04,
// white paper 0.8).
Eigen::Vector3f board_albedo(const Eigen::Vector3f& p);

}  // namespace probeless::sim

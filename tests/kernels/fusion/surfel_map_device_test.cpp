// The HDR surfel map on the device (kernels/fusion/surfel_map.hpp) against its CPU reference
// (surfel_map_reference.hpp) on the reference's own scenes: the ray-cast floor and box of
// tests/unit/fusion (support/surfel_scenes.hpp) and the sim's box_appears / box_removed with
// noisy depth; bad inputs; and the cost (disabled, run with --gtest_also_run_disabled_tests).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <unordered_map>
#include <vector>

#include "drivers/sim/sim_moving_scene.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "kernels/fusion/surfel_map.hpp"
#include "kernels/fusion/surfel_map_reference.hpp"
#include "support/cl_context.hpp"
#include "support/surfel_scenes.hpp"

namespace probeless::fusion {
namespace {

using probeless::testing::AlignedBox;
using probeless::testing::cl_context;
using probeless::testing::looking_down;
using probeless::testing::render;
using probeless::testing::View;

// The tolerances against the reference. The device repeats the reference's arithmetic in its
// order (contraction off, correctly rounded division and sqrt, the radial weights and the
// 8-bit linearisation computed on the host by the same std:: calls), so its decisions (which
// pixel is a candidate, which surfel it fuses into, which surfel is violated, stale or
// evicted) are the reference's unless a value rounds to the other side of a threshold; the
// order of the surfels is the reference's too (kept ones in order, births row-major). What
// is left is rounding: Eigen may order a sum differently from the kernel's, a few ulps that
// grow by at most a factor of the sightings' count through the running averages.
//   - counts (the map's and each SurfelIntegrationStats field) within 0.1 % (+1): a decision
//     that rounds the other way, which these scenes did not show (they agree exactly);
//   - matched surfels (the nearest in the other map within kMatchRadius) within 1e-5 m in
//     position and radius, 1e-4 in normal (the chord: radians at these angles), 1e-5 relative in
//     radiance and confidence, and the same flags and frames; at least 99.9 % of either map matched
//     so.
constexpr double kCountTolerance = 0.001;
constexpr float kMatchRadius = 5e-4f;  // a quarter of the floor's 1.9 mm pixel spacing at 1 m
constexpr float kPositionTolerance = 1e-5f;
constexpr float kNormalTolerance = 1e-4f;
constexpr float kRelativeTolerance = 1e-5f;
constexpr double kMatchedShare = 0.999;

void expect_count_near(std::size_t device, std::size_t reference, const std::string& what) {
  EXPECT_LE(std::abs(static_cast<double>(device) - static_cast<double>(reference)),
            kCountTolerance * static_cast<double>(reference) + 1)
      << what << ": device " << device << ", reference " << reference;
}

void expect_stats_near(const SurfelIntegrationStats& d, const SurfelIntegrationStats& r,
                       const std::string& where) {
  expect_count_near(d.candidates, r.candidates, where + " candidates");
  expect_count_near(d.fused, r.fused, where + " fused");
  expect_count_near(d.born, r.born, where + " born");
  expect_count_near(d.removed_violation, r.removed_violation, where + " removed_violation");
  expect_count_near(d.removed_unstable, r.removed_unstable, where + " removed_unstable");
  expect_count_near(d.evicted, r.evicted, where + " evicted");
}

struct Agreement {
  std::size_t matched = 0;   // of `from`, a partner in `to` within every tolerance
  std::size_t in_place = 0;  // of those, the one at the same index
  float max_position = 0, max_normal = 0, max_relative = 0;
};

struct Errors {
  float position = 0, normal = 0, relative = 0;
  bool same_labels = false;  // flags and frames
  bool within() const {
    return position <= kPositionTolerance && normal <= kNormalTolerance &&
           relative <= kRelativeTolerance && same_labels;
  }
};

Errors errors(const Surfel& a, const Surfel& b) {
  Errors e;
  e.position = std::max((a.position - b.position).norm(), std::abs(a.radius - b.radius));
  // The chord, not acos of the dot: acos(1 - 6e-8), one rounding off two equal unit vectors'
  // dot, is already 3.5e-4 rad.
  e.normal = (a.normal - b.normal).norm();
  const auto rel = [](float x, float ref) {
    return std::abs(x - ref) / std::max(std::abs(ref), 1e-6f);
  };
  e.relative = rel(a.confidence, b.confidence);
  for (int c = 0; c < 3; ++c) e.relative = std::max(e.relative, rel(a.radiance[c], b.radiance[c]));
  e.same_labels = a.flags == b.flags && a.created_frame == b.created_frame &&
                  a.last_seen_frame == b.last_seen_frame;
  return e;
}

// Each surfel of `from` against its partner in `to`: the one at the same index (the device
// keeps the reference's order), else the nearest born on the same frame within kMatchRadius
// (a decision taken the other way shifts the indices after it). Born on the same frame, two
// surfels are a pixel apart (~3 mm at the sim's 1.7 m); of different frames, a newborn may
// lie beside a fused surfel.
Agreement agree(const std::vector<Surfel>& from, const std::vector<Surfel>& to) {
  const auto key = [](const Eigen::Vector3f& p, std::int64_t frame, int dx, int dy, int dz) {
    const auto c = [](float v, int d) {
      return static_cast<std::int64_t>(std::floor(v / kMatchRadius)) + d;
    };
    return (c(p.x(), dx) * 73856093) ^ (c(p.y(), dy) * 19349663) ^ (c(p.z(), dz) * 83492791) ^
           (frame * 2654435761);
  };
  std::unordered_multimap<std::int64_t, std::size_t> grid;
  Agreement a;
  const auto note = [&](const Errors& e) {
    a.max_position = std::max(a.max_position, e.position);
    a.max_normal = std::max(a.max_normal, e.normal);
    a.max_relative = std::max(a.max_relative, e.relative);
  };
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Surfel& s = from[i];
    if (i < to.size()) {
      const Errors e = errors(to[i], s);
      if (e.within()) {
        note(e);
        ++a.matched;
        ++a.in_place;
        continue;
      }
    }
    if (grid.empty())
      for (std::size_t j = 0; j < to.size(); ++j)
        grid.emplace(key(to[j].position, to[j].created_frame, 0, 0, 0), j);
    const Surfel* best = nullptr;
    float best_d = kMatchRadius;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto [b, e] = grid.equal_range(key(s.position, s.created_frame, dx, dy, dz));
          for (auto it = b; it != e; ++it) {
            const Surfel& t = to[it->second];
            const float d = (t.position - s.position).norm();
            if (t.created_frame == s.created_frame && d <= best_d) best_d = d, best = &t;
          }
        }
    if (!best) continue;
    const Errors e = errors(*best, s);
    note(e);
    a.matched += e.within();
  }
  return a;
}

// The two maps agree within the tolerances above; `where` names the frame in the messages.
void expect_maps_agree(SurfelMapDevice& device, const SurfelMap& reference,
                       const std::string& where) {
  const std::vector<Surfel> d = device.download();
  const std::vector<Surfel>& r = reference.surfels();
  expect_count_near(d.size(), r.size(), where + " surfels");
  const Agreement forward = agree(r, d), backward = agree(d, r);
  std::printf(
      "%s: %zu device / %zu reference surfels, %zu matched (%zu in place); max errors: "
      "position or radius %.2g m, normal %.2g, confidence or radiance %.2g relative\n",
      where.c_str(), d.size(), r.size(), forward.matched, forward.in_place,
      std::max(forward.max_position, backward.max_position),
      std::max(forward.max_normal, backward.max_normal),
      std::max(forward.max_relative, backward.max_relative));
  EXPECT_GE(static_cast<double>(forward.matched), kMatchedShare * static_cast<double>(r.size()))
      << where << ": reference surfels with a device partner (max position / radius error "
      << forward.max_position << " m, normal " << forward.max_normal << " rad, relative "
      << forward.max_relative << ")";
  EXPECT_GE(static_cast<double>(backward.matched), kMatchedShare * static_cast<double>(d.size()))
      << where << ": device surfels with a reference partner";
}

// Both maps, one frame.
struct Pair {
  SurfelMap reference;
  SurfelMapDevice device;
  explicit Pair(const SurfelMapParams& p) : reference(p), device(cl_context(), p) {}
  std::pair<SurfelIntegrationStats, SurfelIntegrationStats> integrate(
      const View& v, std::int64_t frame, std::array<float, 3> radiance_per_unit = {1, 1, 1}) {
    const auto r =
        reference.integrate(v.depth, v.colour, radiance_per_unit, v.k, v.T_world_camera, frame);
    const auto d =
        device.integrate(v.depth, v.colour, radiance_per_unit, v.k, v.T_world_camera, frame);
    expect_stats_near(d, r, "frame " + std::to_string(frame));
    return {d, r};
  }
};

SurfelMapParams everywhere() {
  SurfelMapParams p;
  p.region_radius_m = 5;
  p.max_surfels = 1000000;  // more than a VGA frame: these tests are not about the budget
  return p;
}

std::size_t count_in(const std::vector<Surfel>& surfels, const AlignedBox& box, double margin) {
  return static_cast<std::size_t>(
      std::count_if(surfels.begin(), surfels.end(),
                    [&](const Surfel& s) { return box.contains(s.position, margin); }));
}

const AlignedBox kBox{{-0.1, -0.1, 0.0}, {0.1, 0.1, 0.2}};
const AlignedBox kAboveFloorInBox{{-0.1, -0.1, 0.02}, {0.1, 0.1, 0.2}};

TEST(SurfelMapDevice, AFloorFromTwoPosesAsTheReference) {
  Pair maps(everywhere());
  const auto [first, first_ref] = maps.integrate(render(looking_down(0, 0, 1.0), {}), 0);
  EXPECT_GT(first.born, 290000u);
  expect_maps_agree(maps.device, maps.reference, "first view");
  const auto [second, second_ref] =
      maps.integrate(render(looking_down(0.007, -0.004, 1.0, 0.01), {}), 1);
  EXPECT_GT(second.fused, 0.97 * static_cast<double>(second.candidates));
  expect_maps_agree(maps.device, maps.reference, "second view");
}

TEST(SurfelMapDevice, ABoxThatAppearsAsTheReferenceUntilStable) {
  Pair maps(everywhere());
  std::int64_t frame = 0;
  for (; frame < 3; ++frame) maps.integrate(render(looking_down(0, 0, 1.0), {}), frame);
  const View with_box = render(looking_down(0, 0, 1.0), kBox);
  for (int i = 0; i < 12; ++i, ++frame) {
    maps.integrate(with_box, frame);
    if (i == 0 || i == 9 || i == 11)
      expect_maps_agree(maps.device, maps.reference, "box frame " + std::to_string(i));
  }
  const auto stable_on_box = [](const std::vector<Surfel>& surfels) {
    return static_cast<std::size_t>(
        std::count_if(surfels.begin(), surfels.end(), [](const Surfel& s) {
          return kAboveFloorInBox.contains(s.position, 0.005) && s.confidence >= 10;
        }));
  };
  const std::vector<Surfel> d = maps.device.download();
  EXPECT_GT(stable_on_box(d), 0.95 * static_cast<double>(count_in(d, kAboveFloorInBox, 0.005)));
  expect_count_near(stable_on_box(d), stable_on_box(maps.reference.surfels()), "stable on the box");
}

TEST(SurfelMapDevice, ARemovedBoxGoesByTheViolationRuleAsInTheReference) {
  Pair maps(everywhere());
  std::int64_t frame = 0;
  for (; frame < 12; ++frame) maps.integrate(render(looking_down(0, 0, 1.0), kBox), frame);
  const auto [gone, gone_ref] = maps.integrate(render(looking_down(0, 0, 1.0), {}), frame);
  EXPECT_GT(gone.removed_violation, 15000u);
  EXPECT_EQ(count_in(maps.device.download(), kAboveFloorInBox, 0.005), 0u);
  expect_maps_agree(maps.device, maps.reference, "after the removal");
}

TEST(SurfelMapDevice, UnstableSurfelsUnseenForTwentyFramesGoAsInTheReference) {
  Pair maps(everywhere());
  const AlignedBox small{{0.3, 0.2, 0.0}, {0.35, 0.25, 0.1}};
  const AlignedBox small_top{{0.3, 0.2, 0.09}, {0.35, 0.25, 0.1}};
  std::int64_t frame = 0;
  for (; frame < 11; ++frame) maps.integrate(render(looking_down(0, 0, 1.0), {}), frame);
  maps.integrate(render(looking_down(0, 0, 1.0), small), frame++);
  const View away = render(looking_down(5, 5, 1.0), {});
  for (int i = 0; i < 20; ++i) maps.integrate(away, frame++);
  EXPECT_GT(count_in(maps.device.download(), small_top, 0.005), 400u) << "20 frames: kept";
  expect_maps_agree(maps.device, maps.reference, "20 frames unseen");
  const auto [last, last_ref] = maps.integrate(away, frame++);
  EXPECT_GT(last.removed_unstable, 400u);
  EXPECT_EQ(count_in(maps.device.download(), small_top, 0.005), 0u) << "21: deleted";
  expect_maps_agree(maps.device, maps.reference, "21 frames unseen");
}

TEST(SurfelMapDevice, ClippedPixelsAsTheReferenceFromHostOrDeviceImages) {
  View v = render(looking_down(0, 0, 1.0), {});
  for (int y = 0; y < v.k.height; ++y)
    for (int x = 0; x < v.k.width; ++x) {
      const std::uint8_t level = x < 200 ? 255 : x < 400 ? 1 : 128;
      for (int c = 0; c < 3; ++c) v.colour.at(x, y, c) = level;
    }
  v.colour.at(500, 240, 0) = 255;
  Pair maps(everywhere());
  maps.integrate(v, 0, {2.0f, 1.0f, 0.5f});
  expect_maps_agree(maps.device, maps.reference, "clipped");
  std::size_t saturated = 0, black = 0;
  for (const Surfel& s : maps.device.download()) {
    saturated += s.flags == kBornSaturated;
    black += s.flags == kBornBlack;
  }
  EXPECT_GT(saturated, 50000u);
  EXPECT_GT(black, 50000u);
  // The same frame from images already on the device (the service's upload): the same map.
  SurfelMapDevice uploaded(cl_context(), everywhere());
  uploaded.integrate(DeviceDepthImage(cl_context(), v.depth),
                     DeviceImageRGB8(cl_context(), v.colour), {2.0f, 1.0f, 0.5f}, v.k,
                     v.T_world_camera, 0);
  const std::vector<Surfel> a = uploaded.download(), b = maps.device.download();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].position, b[i].position) << i;
    ASSERT_EQ(a[i].confidence, b[i].confidence) << i;
    ASSERT_EQ(a[i].radiance, b[i].radiance) << i;
  }
}

// The eviction's order is total (shell, confidence, index) and the device's surfels are in
// the reference's order, so the survivors are the same surfels.
TEST(SurfelMapDevice, TheBudgetEvictsTheReferencesSurfels) {
  for (const float shell : {0.05f, 100.0f}) {
    SurfelMapParams p = everywhere();
    p.region_centre = {0.3f, 0.1f, 0.0f};
    p.max_surfels = 20000;
    p.eviction_shell_m = shell;
    Pair maps(p);
    const auto [first, first_ref] = maps.integrate(render(looking_down(0, 0, 1.0), {}), 0);
    EXPECT_EQ(maps.device.size(), 20000u);
    EXPECT_EQ(first.evicted, first_ref.evicted);
    expect_maps_agree(maps.device, maps.reference, "shell " + std::to_string(shell) + " frame 0");
    maps.integrate(render(looking_down(0.003, 0, 1.0), {}), 1);
    EXPECT_EQ(maps.device.download().size(), 20000u);
    expect_maps_agree(maps.device, maps.reference, "shell " + std::to_string(shell) + " frame 1");
  }
}

TEST(SurfelMapDevice, PixelsOutsideTheRegionAndOddSizesAsTheReference) {
  SurfelMapParams p;
  p.region_centre = {0.2f, 0.0f, 0.0f};
  p.region_radius_m = 0.1f;
  Pair maps(p);
  maps.integrate(render(looking_down(0, 0, 1.0), {}), 0);
  EXPECT_GT(maps.device.size(), 8000u);
  expect_maps_agree(maps.device, maps.reference, "region");
  // Partial work-groups, frames smaller than the normal stencil, a change of size.
  for (const auto& [w, h] : probeless::testing::kernel_test_sizes()) {
    Pair sized(everywhere());
    const View v = render(looking_down(0, 0, 1.0), kBox, w, h);
    sized.integrate(v, 0);
    sized.integrate(render(looking_down(0.002, 0, 1.0), kBox, w, h), 1);
    expect_maps_agree(sized.device, sized.reference, std::to_string(w) + "x" + std::to_string(h));
  }
}

TEST(SurfelMapDevice, SizesThatDoNotMatchTheIntrinsicsThrow) {
  SurfelMapDevice map(cl_context());
  const View v = render(looking_down(0, 0, 1.0), {}, 64, 48);
  PinholeIntrinsics k = v.k;
  EXPECT_NO_THROW(map.integrate(v.depth, v.colour, {1, 1, 1}, k, v.T_world_camera, 0));
  const auto message = [&](const DepthImage& d, const ImageRGB8& c, std::array<float, 3> e,
                           const PinholeIntrinsics& ki) {
    return testing::integrate_error(map, d, c, e, ki, v.T_world_camera);
  };
  EXPECT_EQ(message(DepthImage(32, 48), v.colour, {1, 1, 1}, k),
            "SurfelMapDevice::integrate: depth is 32x48, intrinsics say 64x48");
  EXPECT_EQ(message(v.depth, ImageRGB8(64, 24), {1, 1, 1}, k),
            "SurfelMapDevice::integrate: colour is 64x24, intrinsics say 64x48");
  EXPECT_NE(message(v.depth, v.colour, {1, 0, 1}, k).find("radiance_per_unit"), std::string::npos);
  k.fx = 0;
  EXPECT_NE(message(v.depth, v.colour, {1, 1, 1}, k).find("focal"), std::string::npos);
  // The device overload checks its images too.
  const auto dd = DeviceDepthImage(cl_context(), DepthImage(32, 48));
  const auto dc = DeviceImageRGB8(cl_context(), v.colour);
  try {
    map.integrate(dd, dc, {1, 1, 1}, v.k, v.T_world_camera, 0);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "SurfelMapDevice::integrate: depth is 32x48, intrinsics say 64x48");
  }
  SurfelMapParams bad;
  bad.max_surfels = 0;
  EXPECT_THROW(SurfelMapDevice(cl_context(), bad), std::invalid_argument);
  bad = {};
  bad.index_scale = 9;
  EXPECT_THROW(SurfelMapDevice(cl_context(), bad), std::invalid_argument);
  EXPECT_EQ(map.size(), map.download().size()) << "the failed calls changed nothing";
}

// The sim's frames (noisy depth, the rig calibration, truth poses) around the judge's sphere.
struct SimFrames {
  PinholeIntrinsics k;
  std::vector<RgbdFrame> frames;
  std::vector<Pose> poses;
};

SimFrames read_sim(const std::string& options, int count) {
  Rig rig = sim::make_sim_rig(sim::parse_sim_options(options));
  SimFrames s{rig.calibration.rgb.intrinsics(), {}, {}};
  for (int i = 0; i < count; ++i) {
    RgbdFrame f;
    EXPECT_EQ(rig.rgbd->read(f, std::chrono::milliseconds(10000)), ReadResult::Frame);
    s.poses.push_back(*f.truth->rig_pose * rig.calibration.T_rig_rgb);
    s.frames.push_back(std::move(f));
  }
  return s;
}

SurfelMapParams sim_region() {
  SurfelMapParams p;
  p.region_centre = sim::light_probe_position().cast<float>();
  p.region_radius_m = 0.5f;
  return p;
}

TEST(SurfelMapDeviceSim, BoxAppearsAndBoxRemovedAsTheReference) {
  for (const char* scene : {"box_appears", "box_removed"}) {
    const SimFrames sim = read_sim(
        std::string("realtime=0,trajectory=static,scene=") + scene + ",start=1.5,frames=20", 20);
    SurfelMap reference(sim_region());
    SurfelMapDevice device(cl_context(), sim_region());
    for (int i = 0; i < 20; ++i) {
      const RgbdFrame& f = sim.frames[static_cast<std::size_t>(i)];
      const auto r = reference.integrate(f.depth, f.colour, {1, 1, 1}, sim.k,
                                         sim.poses[static_cast<std::size_t>(i)], i);
      const auto d = device.integrate(f.depth, f.colour, {1, 1, 1}, sim.k,
                                      sim.poses[static_cast<std::size_t>(i)], i);
      const std::string where = std::string(scene) + " frame " + std::to_string(i);
      expect_stats_near(d, r, where);
      if (i == 0 || i == 15 || i == 19) expect_maps_agree(device, reference, where);
    }
  }
}

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// p50 wall and CPU (every thread of the process: PoCL's workers too) per frame, the device
// and the reference on the same frames; the first frame (the map's birth) apart.
template <typename Integrate>
void time_frames(const char* what, int frames, Integrate&& integrate) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < frames; ++i) {
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    integrate(i);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    cpu.push_back(1e3 * (cpu_seconds() - c0));
  }
  const double first = wall.front(), first_cpu = cpu.front();
  std::sort(wall.begin() + 1, wall.end());
  std::sort(cpu.begin() + 1, cpu.end());
  const std::size_t mid = 1 + (wall.size() - 1) / 2;
  std::printf("%s: first frame %.2f ms (%.2f CPU-ms), then p50 %.2f ms wall, %.2f CPU-ms\n", what,
              first, first_cpu, wall[mid], cpu[mid]);
}

TEST(SurfelMapDevice, DISABLED_CostVga) {
  const View v = render(looking_down(0, 0, 1.0), kBox);
  SurfelMapDevice device(cl_context(), everywhere());
  time_frames("surfel map device, 640x480 everywhere", 30, [&](int i) {
    device.integrate(v.depth, v.colour, {1, 1, 1}, v.k, v.T_world_camera, i);
  });
  std::printf("  %zu surfels (%s)\n", device.size(), cl_context().describe().c_str());
  SurfelMap reference(everywhere());
  time_frames("surfel map reference, the same", 10, [&](int i) {
    reference.integrate(v.depth, v.colour, {1, 1, 1}, v.k, v.T_world_camera, i);
  });
}

TEST(SurfelMapDeviceSim, DISABLED_CostBoxAppears) {
  const SimFrames sim =
      read_sim("realtime=0,trajectory=static,scene=box_appears,start=1.5,frames=30", 30);
  SurfelMapDevice device(cl_context(), sim_region());
  std::size_t candidates = 0;
  time_frames("surfel map device, sim box_appears, region 0.5 m", 30, [&](int i) {
    const auto& f = sim.frames[static_cast<std::size_t>(i)];
    candidates += device
                      .integrate(f.depth, f.colour, {1, 1, 1}, sim.k,
                                 sim.poses[static_cast<std::size_t>(i)], i)
                      .candidates;
  });
  std::printf("  %zu surfels, %zu candidate pixels a frame (%s)\n", device.size(), candidates / 30,
              cl_context().describe().c_str());
  SurfelMap reference(sim_region());
  time_frames("surfel map reference, the same", 30, [&](int i) {
    const auto& f = sim.frames[static_cast<std::size_t>(i)];
    reference.integrate(f.depth, f.colour, {1, 1, 1}, sim.k, sim.poses[static_cast<std::size_t>(i)],
                        i);
  });
}

}  // namespace
}  // namespace probeless::fusion

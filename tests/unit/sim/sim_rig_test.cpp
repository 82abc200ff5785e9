#include "drivers/sim/sim_rig.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "drivers/sim/sim_trace.hpp"
#include "drivers/sim/sim_world.hpp"

namespace probeless::sim {
namespace {

using std::chrono::milliseconds;

Rig open(const std::string& spec) {
  return make_sim_rig(parse_sim_options(spec));
}

RgbdFrame read_rgbd(Rig& rig) {
  RgbdFrame f;
  EXPECT_EQ(rig.rgbd->read(f, milliseconds(1000)), ReadResult::Frame);
  return f;
}

FisheyeFrame read_fisheye(Rig& rig) {
  FisheyeFrame f;
  EXPECT_EQ(rig.fisheye->read(f, milliseconds(1000)), ReadResult::Frame);
  return f;
}

TEST(SimOptions, ParsesEveryKey) {
  const SimOptions o = parse_sim_options(
      "seed=3,trajectory=static,fps=60,fisheye_fps=50,realtime=0,stall=60:120,frames=500,"
      "fisheye_size=256,fisheye_bits=8,fisheye_fov=185,truth=0,threads=1,start=4.5,prerender=7,"
      "fisheye_scenes=12,stamp_on_read=1");
  EXPECT_EQ(o.seed, 3u);
  EXPECT_EQ(o.trajectory, TrajectoryKind::Static);
  EXPECT_EQ(o.rgbd_fps, 60);
  EXPECT_EQ(o.fisheye_fps, 50);
  EXPECT_FALSE(o.realtime);
  EXPECT_EQ(o.stall_begin, 60);
  EXPECT_EQ(o.stall_end, 120);
  EXPECT_EQ(o.max_frames, 500);
  EXPECT_EQ(o.fisheye_size, 256);
  EXPECT_EQ(o.fisheye_bit_depth, 8);
  EXPECT_EQ(o.fisheye_fov_deg, 185);
  EXPECT_FALSE(o.ground_truth);
  EXPECT_EQ(o.render_threads, 1);
  EXPECT_EQ(o.start_s, 4.5);
  EXPECT_EQ(o.prerender, 7);
  EXPECT_EQ(o.fisheye_scenes, 12);
  EXPECT_TRUE(o.stamp_on_read);
  EXPECT_FALSE(o.fisheye_realtime.has_value()) << "unset: follows realtime";
  EXPECT_EQ(parse_sim_options("realtime=0,fisheye_realtime=1").fisheye_realtime, true);
  EXPECT_EQ(parse_sim_options("seed=1").seed, 1u);
  EXPECT_EQ(parse_sim_options("").seed, SimOptions{}.seed);
}

TEST(SimOptions, ErrorsNameTheKey) {
  for (const char* spec :
       {"sed=3", "seed=x", "trajectory=spiral", "stall=5", "fisheye_bits=10", "fisheye_size=4096",
        "fps=-1", "realtime=maybe", "fisheye_realtime=2", "start=-1", "start=soon", "prerender=-1",
        "prerender=lots", "fisheye_scenes=-4"}) {
    try {
      parse_sim_options(spec);
      ADD_FAILURE() << spec << " was accepted";
    } catch (const std::invalid_argument& e) {
      const std::string key(spec, std::string_view(spec).find('='));
      EXPECT_NE(std::string(e.what()).find("'" + key + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(SimRig, SameSeedSameFrames) {
  Rig a = open("seed=5,realtime=0,trajectory=handheld");
  Rig b = open("seed=5,realtime=0,trajectory=handheld");
  for (int i = 0; i < 4; ++i) {
    const RgbdFrame fa = read_rgbd(a), fb = read_rgbd(b);
    EXPECT_EQ(fa.sequence, fb.sequence);
    EXPECT_TRUE(fa.colour == fb.colour) << "frame " << i;
    EXPECT_TRUE(fa.depth == fb.depth) << "frame " << i;
    EXPECT_TRUE(fa.truth->clean_depth == fb.truth->clean_depth);
    EXPECT_TRUE(fa.truth->occluder_mask == fb.truth->occluder_mask);
  }
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(read_fisheye(a).raw == read_fisheye(b).raw);
  }
  Rig c = open("seed=6,realtime=0,trajectory=handheld");
  Rig d = open("seed=5,realtime=0,trajectory=handheld");
  EXPECT_FALSE(read_rgbd(c).colour == read_rgbd(d).colour);
}

// Prerendered frames are the frames the sim renders live (bench pipeline --prerender measures
// the same pipeline work), past them it renders live again, and the fisheye still applies the
// exposure asked for at the read.
TEST(SimRig, PrerenderedFramesAreTheLiveOnes) {
  Rig live = open("seed=4,realtime=0");
  Rig pre = open("seed=4,realtime=0,prerender=3");
  for (int i = 0; i < 5; ++i) {  // 3 from memory, then 2 live
    const RgbdFrame a = read_rgbd(live), b = read_rgbd(pre);
    EXPECT_EQ(a.sequence, b.sequence);
    EXPECT_TRUE(a.colour == b.colour) << "frame " << i;
    EXPECT_TRUE(a.depth == b.depth) << "frame " << i;
    EXPECT_TRUE(a.truth->clean_depth == b.truth->clean_depth) << "frame " << i;
  }
  ExposureStamp dark;
  dark.exposure.time_s = 0.001;
  ExposureStamp bright = dark;
  bright.exposure.time_s = 0.004;
  for (int i = 0; i < 4; ++i) {
    const ExposureStamp& e = i % 2 ? bright : dark;
    live.fisheye->set_next_exposure(e);
    pre.fisheye->set_next_exposure(e);
    const FisheyeFrame a = read_fisheye(live), b = read_fisheye(pre);
    EXPECT_TRUE(a.raw == b.raw) << "fisheye frame " << i;
    EXPECT_EQ(b.exposure.exposure.time_s, e.exposure.time_s);
    ASSERT_TRUE(b.truth && b.truth->rig_pose);
    EXPECT_TRUE(a.truth->rig_pose->translation.isApprox(b.truth->rig_pose->translation));
  }
}

// With fisheye_repeat the fisheye serves its prerendered scenes again instead of casting rays
// (bench pipeline --prerender below 50 fps): frame 3 of 2 prerendered shows frame 1's scene,
// with its own timestamp and the exposure asked for.
TEST(SimRig, FisheyeRepeatServesThePrerenderedScenesAgain) {
  // One fisheye frame a second: the orbit turns the view between frames 1 and 3 by far more
  // than the sensor noise differs.
  Rig live = open("seed=4,realtime=0,truth=0,fisheye_fps=1");
  Rig rep = open("seed=4,realtime=0,truth=0,fisheye_fps=1,prerender=2,fisheye_repeat=1");
  ExposureStamp e;
  e.exposure.time_s = 0.002;
  live.fisheye->set_next_exposure(e);
  rep.fisheye->set_next_exposure(e);
  std::vector<FisheyeFrame> a, b;
  for (int i = 0; i < 4; ++i) {
    a.push_back(read_fisheye(live));
    b.push_back(read_fisheye(rep));
  }
  EXPECT_TRUE(a[1].raw == b[1].raw) << "a prerendered frame is the live one";
  EXPECT_FALSE(a[3].raw == b[3].raw) << "past the prerendered frames it does not render live";
  // Frame 3 repeats frame 1's scene; the sensor noise is drawn per frame index, so compare
  // the mean level rather than the bits.
  double d31 = 0, d3live = 0;
  for (std::size_t k = 0; k < b[3].raw.pixel_count() * 3; ++k) {
    d31 += std::abs(double(b[3].raw.data()[k]) - double(b[1].raw.data()[k]));
    d3live += std::abs(double(b[3].raw.data()[k]) - double(a[3].raw.data()[k]));
  }
  EXPECT_LT(d31, d3live) << "frame 3 is frame 1's scene again, not frame 3's";
  EXPECT_GT(b[3].timestamp_ns, b[2].timestamp_ns);
  EXPECT_EQ(b[3].exposure.exposure.time_s, e.exposure.time_s);
}

// fisheye_scenes: the fisheye cycles that many prerendered scenes and keeps each exposed frame,
// so a scene seen again at the same exposure is the same picture (no sensor model work), and a
// new exposure is exposed anew.
TEST(SimRig, FisheyeScenesKeepTheExposedFramesForTheirRepeats) {
  Rig full = open("seed=4,realtime=0,truth=0,fisheye_fps=1,prerender=6,fisheye_repeat=1");
  Rig few =
      open("seed=4,realtime=0,truth=0,fisheye_fps=1,prerender=6,fisheye_repeat=1,fisheye_scenes=2");
  ExposureStamp e;
  e.exposure.time_s = 0.002;
  full.fisheye->set_next_exposure(e);
  few.fisheye->set_next_exposure(e);
  std::vector<FisheyeFrame> b;
  const FisheyeFrame first = read_fisheye(full);
  for (int i = 0; i < 4; ++i) b.push_back(read_fisheye(few));
  EXPECT_TRUE(b[0].raw == first.raw) << "the first pass is the sensor model's";
  EXPECT_FALSE(b[1].raw == b[0].raw);
  EXPECT_TRUE(b[2].raw == b[0].raw) << "scene 0 again at the same exposure: the kept frame";
  EXPECT_TRUE(b[3].raw == b[1].raw);
  EXPECT_EQ(b[3].sequence, 3u);
  EXPECT_GT(b[3].timestamp_ns, b[2].timestamp_ns);
  e.exposure.time_s = 0.004;
  few.fisheye->set_next_exposure(e);
  const FisheyeFrame brighter = read_fisheye(few);  // scene 0, exposed anew
  EXPECT_EQ(brighter.exposure.exposure.time_s, 0.004);
  double level0 = 0, level4 = 0;
  for (std::size_t k = 0; k < brighter.raw.pixel_count() * 3; ++k) {
    level0 += b[0].raw.data()[k] - double(b[0].black_level);
    level4 += brighter.raw.data()[k] - double(brighter.black_level);
  }
  // Above black; less than 2x where the window clips.
  EXPECT_GT(level4, 1.5 * level0) << "twice the exposure, not the kept frame";
}

// stamp_on_read: a prerendered frame read late carries the time it was read, not its place
// on the 30 Hz sim clock.
TEST(SimRig, StampOnReadGivesTheTimeAFrameIsRead) {
  Rig rig = open("seed=4,realtime=0,truth=0,prerender=3,stamp_on_read=1");
  const TimestampNs before = monotonic_now_ns();
  const RgbdFrame a = read_rgbd(rig);
  EXPECT_GE(a.timestamp_ns, before);
  EXPECT_LE(a.timestamp_ns, monotonic_now_ns());
  std::this_thread::sleep_for(std::chrono::milliseconds(80));
  const RgbdFrame b = read_rgbd(rig);
  EXPECT_GE(b.timestamp_ns - a.timestamp_ns, 80'000'000) << "the sim clock would say 33 ms";
  const RgbdFrame c = read_rgbd(rig);
  EXPECT_GT(c.timestamp_ns, b.timestamp_ns);
}

TEST(SimRig, PrerenderRestartsTheClockAfterRendering) {
  const TimestampNs before = monotonic_now_ns();
  Rig pre = open("seed=4,realtime=0,prerender=4");
  const TimestampNs after = monotonic_now_ns();
  const RgbdFrame f = read_rgbd(pre);
  EXPECT_GE(f.timestamp_ns, before + (after - before) / 2)
      << "frame 0's time is when the frames could flow, not before the rendering";
}

TEST(SimRig, ThreadCountDoesNotChangeTheFrames) {
  Rig a = open("seed=2,realtime=0,threads=1");
  Rig b = open("seed=2,realtime=0,threads=3");
  const RgbdFrame fa = read_rgbd(a), fb = read_rgbd(b);
  EXPECT_TRUE(fa.colour == fb.colour);
  EXPECT_TRUE(fa.depth == fb.depth);
  EXPECT_TRUE(read_fisheye(a).raw == read_fisheye(b).raw);
}

TEST(SimRig, CalibrationLooksForwardAndUp) {
  Rig rig = open("realtime=0,trajectory=static");
  const RigCalibration& cal = rig.calibration;
  EXPECT_EQ(cal.rgb.width(), 640);
  EXPECT_EQ(cal.rgb.intrinsics().fx, 525);
  ASSERT_TRUE(cal.fisheye);
  EXPECT_EQ(cal.fisheye->width(), 512);
  const RgbdFrame f = read_rgbd(rig);
  const Pose T_world_rig = *f.truth->rig_pose;
  const Eigen::Vector3d up = (T_world_rig * cal.T_rig_fisheye).rotation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(up.z(), 1.0, 1e-9) << "the fisheye's optical axis is world +z";
  const Eigen::Vector3d forward = (T_world_rig * cal.T_rig_rgb).rotation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(forward.z(), 0.0, 1e-9) << "the colour camera looks horizontally";
  // The anchor is in view, on the table top.
  const Eigen::Vector3d anchor_cam = (T_world_rig * cal.T_rig_rgb).inverse() * object_anchor();
  const auto px = cal.rgb.project(anchor_cam);
  ASSERT_TRUE(px);
  EXPECT_TRUE(cal.rgb.in_image(*px));
  EXPECT_NEAR(object_anchor().z(), table_top_height_m(), 1e-12);
  const int u = static_cast<int>(std::lround(px->x())), v = static_cast<int>(std::lround(px->y()));
  EXPECT_NEAR(f.truth->clean_depth.at(u, v) / 1000.0, anchor_cam.z(), 0.01);
}

// Where the mask says "occluder", the clean depth is the arm's own depth along that ray.
TEST(SimRig, OccluderMaskAgreesWithCleanDepth) {
  Rig rig = open("seed=1,realtime=0,trajectory=static,fps=10");
  const auto world = std::make_shared<const SimWorld>(1);
  const PinholeIntrinsics k = rig.calibration.rgb.intrinsics();
  int masked = 0;
  for (int i = 0; i < 50; ++i) {
    const RgbdFrame f = read_rgbd(rig);
    const Pose cam = *f.truth->rig_pose * rig.calibration.T_rig_rgb;
    const Occluder arm = world->occluder(f.sequence / 10.0, cam.translation);
    const Eigen::Matrix3f r = cam.rotation.toRotationMatrix().cast<float>();
    for (int y = 0; y < 480; y += 2) {
      for (int x = 0; x < 640; x += 2) {
        if (f.truth->occluder_mask.at(x, y) != 255) continue;
        ++masked;
        const Eigen::Vector3f d = r * Eigen::Vector3f((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1);
        const Ray ray(cam.translation.cast<float>(), d);
        float best = 1e9f;
        for (const Capsule& c : arm.capsules) {
          float t;
          if (hit_capsule(ray, c, t)) best = std::min(best, t);
        }
        ASSERT_LT(best, 1e9f) << "masked pixel (" << x << ", " << y << ") misses the arm";
        ASSERT_NEAR(f.truth->clean_depth.at(x, y), best * 1000, 1.0);
      }
    }
  }
  EXPECT_GT(masked, 500) << "the arm crosses the view within five seconds";
}

TEST(SimRig, ArmPassesInFrontOfTheAnchorPeriodically) {
  Rig rig = open("realtime=0,trajectory=orbit,fps=10");
  int covered = 0, clear = 0;
  for (int i = 0; i < 100; ++i) {  // ten seconds
    const RgbdFrame f = read_rgbd(rig);
    const Pose cam = *f.truth->rig_pose * rig.calibration.T_rig_rgb;
    const auto px = rig.calibration.rgb.project(cam.inverse() * light_probe_position());
    ASSERT_TRUE(px && rig.calibration.rgb.in_image(*px));
    const bool hidden =
        f.truth->occluder_mask.at(static_cast<int>(px->x()), static_cast<int>(px->y())) == 255;
    (hidden ? covered : clear)++;
  }
  EXPECT_GE(covered, 4);
  EXPECT_GE(clear, 50);
}

TEST(SimRig, LightChangesOnlyWithTheLamps) {
  Rig rig = open("realtime=0,trajectory=static,fps=1");
  std::vector<std::shared_ptr<const Cubemap>> lights;
  for (int i = 0; i < 13; ++i) lights.push_back(read_rgbd(rig).truth->light);
  EXPECT_EQ(lights[0], lights[5]) << "the same lamps give the same shared cubemap";
  EXPECT_NE(lights[5], lights[6]) << "lamp B switches off at 6 s";
  EXPECT_EQ(lights[0], lights[12]) << "and on again at 12 s";
  EXPECT_GE(lights[0]->face_size, 32);
  // The bright window against the dark corners: at least 1e4 : 1.
  float lo = 1e30f, hi = 0;
  for (const auto& face : lights[6]->faces) {
    for (std::size_t i = 0; i < face.pixel_count(); ++i) {
      const float* c = face.data() + 3 * i;
      const float y = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
  }
  EXPECT_GE(hi / lo, 1e4f);
}

// start=S moves the scripted world, not the timestamps: started at 5 s, the sixth frame at
// 1 fps is already past the 6 s lamp switch, and the first frame sees the orbit at 5 s.
TEST(SimRig, StartOffsetsTheScriptedWorld) {
  Rig late = open("realtime=0,fps=1,start=5");
  Rig early = open("realtime=0,fps=1");
  const RgbdFrame l0 = read_rgbd(late);
  std::vector<RgbdFrame> e;
  for (int i = 0; i < 6; ++i) e.push_back(read_rgbd(early));
  ASSERT_TRUE(l0.truth->rig_pose && e[5].truth->rig_pose);
  EXPECT_LT((l0.truth->rig_pose->translation - e[5].truth->rig_pose->translation).norm(), 1e-9);
  EXPECT_EQ(l0.truth->light, e[5].truth->light) << "lamp B still on at 5 s";
  const RgbdFrame l1 = read_rgbd(late);
  EXPECT_NE(l1.truth->light, l0.truth->light) << "and off at 6 s";
  EXPECT_EQ(l1.timestamp_ns - l0.timestamp_ns, 1'000'000'000) << "timestamps step as before";
}

// Mean linear intensity of an 8-bit gamma-2.2 image, and its log-mean (floored at 1e-3).
std::pair<double, double> linear_means(const ImageRGB8& image) {
  double sum = 0, log_sum = 0;
  for (std::uint8_t v : image.elements()) {
    const double l = std::pow(v / 255.0, 2.2);
    sum += l;
    log_sum += std::log(std::max(l, 1e-3));
  }
  const auto n = static_cast<double>(image.elements().size());
  return {sum / n, std::exp(log_sum / n)};
}

TEST(SimRig, AutoExposureMapsMidGreyAndFollowsTheLampWithLag) {
  Rig rig = open("realtime=0,trajectory=static,fps=10,truth=0");
  std::vector<double> mean;
  for (int i = 0; i < 70; ++i) {
    const RgbdFrame f = read_rgbd(rig);
    const auto [m, log_mean] = linear_means(f.colour);
    mean.push_back(m);
    // The scene's log-mean maps near 0.18 (below it where the window clips at white).
    if (i == 50) {
      EXPECT_NEAR(log_mean, 0.18, 0.06);
    }
  }
  // Lamp B switches off at 6 s (frame 60): the picture darkens, then the exposure catches up
  // over a few frames, not at once and not never.
  EXPECT_LT(mean[60], 0.95 * mean[59]);
  EXPECT_GT(mean[62], mean[60]);
  EXPECT_LT(mean[62], mean[68]);
  EXPECT_NEAR(mean[69], mean[59], 0.02 * mean[59]);
}

TEST(SimRig, FisheyeTakesTheExposureItIsTold) {
  Rig rig = open("realtime=0,trajectory=static");
  ExposureStamp e;
  e.exposure = {0.002, 0.0};
  e.level = BracketLevel::Low;
  rig.fisheye->set_next_exposure(e);
  const FisheyeFrame a = read_fisheye(rig);
  EXPECT_EQ(a.exposure, e);
  e.exposure.time_s = 0.004;
  rig.fisheye->set_next_exposure(e);
  const FisheyeFrame b = read_fisheye(rig);
  EXPECT_EQ(b.exposure.exposure.time_s, 0.004);
  EXPECT_EQ(a.bit_depth, 12);
  // Twice the exposure, twice the signal above black where neither frame saturates.
  double sa = 0, sb = 0;
  int saturated = 0;
  for (std::size_t i = 0; i < a.raw.elements().size(); ++i) {
    const int va = a.raw.data()[i], vb = b.raw.data()[i];
    if (vb >= 4095) {
      ++saturated;
      continue;
    }
    sa += va - a.black_level;
    sb += vb - b.black_level;
  }
  EXPECT_NEAR(sb / sa, 2.0, 0.05);
  EXPECT_GT(saturated, 0) << "the window saturates at 4 ms";
}

TEST(SimRig, FisheyeEightBitHasItsOwnBlackAndWhite) {
  Rig rig = open("realtime=0,trajectory=static,fisheye_bits=8,fisheye_size=128");
  ExposureStamp e;
  e.exposure = {0.02, 12.0};  // long enough to saturate the window and the lamps
  rig.fisheye->set_next_exposure(e);
  const FisheyeFrame f = read_fisheye(rig);
  EXPECT_EQ(f.bit_depth, 8);
  EXPECT_EQ(f.black_level, 16);
  EXPECT_EQ(f.raw.width(), 128);
  const auto [lo, hi] = std::minmax_element(f.raw.elements().begin(), f.raw.elements().end());
  EXPECT_EQ(*hi, 255) << "saturated";
  EXPECT_LT(*lo, 24) << "outside the image circle: black level and read noise";
}

TEST(SimRig, EndsAfterMaxFrames) {
  Rig rig = open("realtime=0,frames=3,fps=30,fisheye_fps=20,truth=0");
  RgbdFrame f;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(rig.rgbd->read(f, milliseconds(100)), ReadResult::Frame);
    EXPECT_FALSE(f.truth);
  }
  EXPECT_EQ(rig.rgbd->read(f, milliseconds(100)), ReadResult::EndOfStream);
  EXPECT_EQ(rig.rgbd->state(), SourceState::Ended);
  FisheyeFrame ff;
  EXPECT_EQ(rig.fisheye->read(ff, milliseconds(100)), ReadResult::Frame);
  EXPECT_EQ(rig.fisheye->read(ff, milliseconds(100)), ReadResult::Frame);
  EXPECT_EQ(rig.fisheye->read(ff, milliseconds(100)), ReadResult::EndOfStream);
}

TEST(SimRig, StallSaysNoSignalThenResumes) {
  Rig rig = open("realtime=0,fps=100,stall=2:5,truth=0");
  RgbdFrame f;
  ASSERT_EQ(rig.rgbd->read(f, milliseconds(100)), ReadResult::Frame);
  ASSERT_EQ(rig.rgbd->read(f, milliseconds(100)), ReadResult::Frame);
  EXPECT_EQ(f.sequence, 1u);
  EXPECT_EQ(rig.rgbd->read(f, milliseconds(0)), ReadResult::NoFrameYet);
  EXPECT_EQ(rig.rgbd->state(), SourceState::NoSignal);
  // Three frames at 100 fps: the stall lasts 30 ms of wall-clock time.
  const auto start = std::chrono::steady_clock::now();
  ReadResult r;
  while ((r = rig.rgbd->read(f, milliseconds(5))) == ReadResult::NoFrameYet) {
  }
  EXPECT_GE(std::chrono::steady_clock::now() - start, milliseconds(20));
  ASSERT_EQ(r, ReadResult::Frame);
  EXPECT_EQ(f.sequence, 5u);
  EXPECT_EQ(rig.rgbd->state(), SourceState::Streaming);
}

TEST(SimRig, RealtimePacesToTheClock) {
  // Two seconds a frame, so that even a sanitizer build renders well within one period.
  Rig rig = open("realtime=1,fps=0.5,truth=0");
  RgbdFrame f;
  ASSERT_EQ(rig.rgbd->read(f, milliseconds(3000)), ReadResult::Frame);
  EXPECT_EQ(f.sequence, 0u);
  const TimestampNs first = f.timestamp_ns;
  if (monotonic_now_ns() - first < 1'000'000'000) {
    EXPECT_EQ(rig.rgbd->read(f, milliseconds(0)), ReadResult::NoFrameYet)
        << "the next frame is two seconds away";
  }
  ASSERT_EQ(rig.rgbd->read(f, milliseconds(3000)), ReadResult::Frame);
  EXPECT_EQ(f.sequence, 1u);
  EXPECT_EQ(f.timestamp_ns - first, 2'000'000'000);
  EXPECT_GE(monotonic_now_ns(), f.timestamp_ns) << "no frame before its time";
}

// bench pipeline's mode: RGB-D as fast as it renders, the fisheye paced at its own rate.
TEST(SimRig, FisheyePacedWhileRgbdRunsFree) {
  Rig rig = open("realtime=0,fisheye_realtime=1,fisheye_fps=0.5,truth=0");
  FisheyeFrame fisheye;
  ASSERT_EQ(rig.fisheye->read(fisheye, milliseconds(3000)), ReadResult::Frame);
  const TimestampNs first = fisheye.timestamp_ns;
  RgbdFrame rgbd;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(rig.rgbd->read(rgbd, milliseconds(0)), ReadResult::Frame) << "RGB-D is not paced";
  }
  if (monotonic_now_ns() - first < 1'000'000'000) {
    EXPECT_EQ(rig.fisheye->read(fisheye, milliseconds(0)), ReadResult::NoFrameYet)
        << "the next fisheye frame is two seconds away";
  }
}

}  // namespace
}  // namespace probeless::sim

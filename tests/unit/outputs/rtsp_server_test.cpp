#include "app/outputs/rtsp_server.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "app/outputs/h264_encoder.hpp"
#include "eventually.hpp"
#include "rtsp_test_client.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using testing::DecodedFrame;
using testing::RtspTestClient;
using Clock = std::chrono::steady_clock;

constexpr int kWidth = 640, kHeight = 480;
constexpr int kCodeTop = 400;  // rows below carry the frame number as 16 black/white blocks
constexpr int kBits = 16;

// Distinct, saturated colours: a decoder that swapped channels or a wrong colour matrix
// lands far outside the tolerance.
constexpr std::array<std::array<int, 3>, 6> kPalette{
    {{220, 40, 40}, {40, 200, 60}, {50, 70, 230}, {240, 220, 50}, {30, 200, 210}, {200, 60, 200}}};

std::array<int, 3> left_colour(int index) {
  return kPalette[static_cast<std::size_t>(index / 5 % 6)];
}
std::array<int, 3> right_colour(int index) {
  return kPalette[static_cast<std::size_t>((index / 5 + 3) % 6)];
}

// Left and right halves in solid colours that change every five frames; the frame number
// in binary along the bottom, so that each decoded frame names the frame it came from.
ImageRGB8 test_frame(int index) {
  ImageRGB8 image(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      std::array<int, 3> c;
      if (y < kCodeTop) {
        c = x < kWidth / 2 ? left_colour(index) : right_colour(index);
      } else {
        const int bit = x / (kWidth / kBits);
        const int v = (index >> bit) & 1 ? 255 : 0;
        c = {v, v, v};
      }
      for (int ch = 0; ch < 3; ++ch) image.at(x, y, ch) = static_cast<std::uint8_t>(c[ch]);
    }
  return image;
}

int read_frame_number(const ImageRGB8& image) {
  const int block = image.width() / kBits;
  const int y = (kCodeTop + image.height()) / 2;
  int index = 0;
  for (int bit = 0; bit < kBits; ++bit)
    if (image.at(bit * block + block / 2, y, 1) > 128) index |= 1 << bit;
  return index;
}

// Mean of a 40x40 patch: away from the edges, where 4:2:0 chroma and the encoder blur.
std::array<double, 3> patch_mean(const ImageRGB8& image, int cx, int cy) {
  std::array<double, 3> sum{};
  for (int y = cy - 20; y < cy + 20; ++y)
    for (int x = cx - 20; x < cx + 20; ++x)
      for (int ch = 0; ch < 3; ++ch) sum[ch] += image.at(x, y, ch);
  for (auto& s : sum) s /= 1600.0;
  return sum;
}

double max_error(const std::array<double, 3>& got, const std::array<int, 3>& want) {
  double e = 0;
  for (int ch = 0; ch < 3; ++ch) e = std::max(e, std::abs(got[ch] - want[ch]));
  return e;
}

// Pushes numbered frames at 30 Hz on its own thread, as the pipeline's output thread does,
// and remembers when each was pushed.
class Feeder {
 public:
  explicit Feeder(RtspServer& server)
      : thread_([this, &server](std::stop_token stop) {
          for (int i = 0; !stop.stop_requested() && i < (1 << kBits); ++i) {
            auto frame = std::make_shared<const ImageRGB8>(test_frame(i));
            {
              std::lock_guard lock(mutex_);
              pushed_at_[i] = Clock::now();
            }
            server.push(std::move(frame), monotonic_now_ns());
            std::this_thread::sleep_for(33ms);
          }
        }) {}
  std::optional<Clock::time_point> pushed_at(int index) const {
    std::lock_guard lock(mutex_);
    auto it = pushed_at_.find(index);
    if (it == pushed_at_.end()) return std::nullopt;
    return it->second;
  }

 private:
  mutable std::mutex mutex_;
  std::map<int, Clock::time_point> pushed_at_;
  std::jthread thread_;
};

RtspServerConfig ephemeral() {
  RtspServerConfig config;
  config.port = 0;
  config.path = "/test";
  return config;
}

struct Received {
  int frames = 0;
  double worst_colour_error = 0;
  std::vector<double> colour_errors;  // per decoded frame, the worse of its two halves
  std::vector<double> latency_ms;

  double share_within(double tolerance) const {
    const auto n = std::count_if(colour_errors.begin(), colour_errors.end(),
                                 [&](double e) { return e < tolerance; });
    return colour_errors.empty() ? 0.0 : static_cast<double>(n) / colour_errors.size();
  }
};

// Decodes for `duration` after the first frame; checks every frame's size, and its colours
// against what was sent under the number it carries.
Received receive(RtspTestClient& client, const Feeder& feeder, std::chrono::milliseconds duration) {
  Received r;
  auto first = client.next(10s);  // RTSP setup, then the next keyframe
  if (!first) {
    ADD_FAILURE() << "no frame within 10 s: " << client.ended();
    return r;
  }
  const auto deadline = Clock::now() + duration;
  for (auto f = std::move(first); f && Clock::now() < deadline; f = client.next(2s)) {
    ++r.frames;
    EXPECT_EQ(f->image.width(), kWidth);
    EXPECT_EQ(f->image.height(), kHeight);
    if (f->image.width() != kWidth || f->image.height() != kHeight) break;
    const int index = read_frame_number(f->image);
    const auto pushed = feeder.pushed_at(index);
    EXPECT_TRUE(pushed.has_value()) << "decoded a frame number never pushed: " << index;
    if (!pushed) continue;
    r.latency_ms.push_back(
        std::chrono::duration<double, std::milli>(f->received - *pushed).count());
    const double error = std::max(
        max_error(patch_mean(f->image, kWidth / 4, kCodeTop / 2), left_colour(index)),
        max_error(patch_mean(f->image, 3 * kWidth / 4, kCodeTop / 2), right_colour(index)));
    r.colour_errors.push_back(error);
    r.worst_colour_error = std::max(r.worst_colour_error, error);
  }
  return r;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

using testing::eventually;

void expect_error(const RtspServerConfig& config, const std::string& fragment) {
  try {
    RtspServer server(config);
    ADD_FAILURE() << "expected RtspServerError containing '" << fragment << "'";
  } catch (const RtspServerError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(RtspServer, StreamsWhatWasPushedToARealClient) {
  RtspServer server(ephemeral());
  EXPECT_EQ(server.url(), "rtsp://127.0.0.1:" + std::to_string(server.port()) + "/test");
  EXPECT_GT(server.port(), 0);
  Feeder feeder(server);
  RtspTestClient client(server.url(), "tcp");
  const Received r = receive(client, feeder, 1500ms);
  EXPECT_GE(r.frames, 20) << "at 30 Hz for 1.5 s";
  // Flat colours at 2 Mbit/s come back within a few levels; 12 allows the RGB->I420->RGB
  // round trip's rounding at saturated colours.
  EXPECT_LT(r.worst_colour_error, 12.0);
  const double p50 = percentile(r.latency_ms, 0.5), p95 = percentile(r.latency_ms, 0.95);
  std::printf(
      "[ rtsp ] %d frames over loopback (tcp), push -> decoded latency p50 %.1f ms, "
      "p95 %.1f ms, worst colour error %.1f\n",
      r.frames, p50, p95, r.worst_colour_error);
  // Under a frame period: measured 3-4 ms p50 on a loaded 2-core machine; an encoder that
  // holds a frame back (x264 given variable-rate caps did: 41 ms) fails here.
  EXPECT_LT(p50, 33.0) << "a frame is held back somewhere";

  const RtspServerStats s = server.stats();
  EXPECT_EQ(s.clients, 1);
  EXPECT_EQ(s.encoder, server.encoder_name());
  EXPECT_GE(s.frames_sent, static_cast<std::uint64_t>(r.frames));
  const nlohmann::json j = to_json(s);
  EXPECT_EQ(j["url"], server.url());
  EXPECT_EQ(j["clients"], 1);
}

TEST(RtspServer, TwoClientsShareTheStream) {
  RtspServer server(ephemeral());
  Feeder feeder(server);
  RtspTestClient tcp(server.url(), "tcp");
  RtspTestClient udp(server.url(), "udp");
  Received a, b;
  std::jthread other([&] { b = receive(udp, feeder, 1000ms); });
  a = receive(tcp, feeder, 1000ms);
  other.join();
  EXPECT_GE(a.frames, 10);
  EXPECT_GE(b.frames, 10);
  EXPECT_LT(a.worst_colour_error, 12.0);
  // RTP over UDP may lose packets when the client's thread is starved (the whole suite on two
  // cores once lost some: one frame decoded from a broken reference, 240 levels off), so over UDP
  // four frames in five must be right; a wrong colour matrix or a stalled encoder fails all.
  EXPECT_GE(b.share_within(12.0), 0.8) << "worst " << b.worst_colour_error;
  const RtspServerStats s = server.stats();
  EXPECT_EQ(s.clients, 2);
  EXPECT_EQ(s.media_created, 1u) << "one shared media, one encoder";
}

TEST(RtspServer, StopsCleanlyWithAClientConnected) {
  RtspServer server(ephemeral());
  Feeder feeder(server);
  RtspTestClient client(server.url());
  ASSERT_TRUE(client.next(10s).has_value()) << client.ended();
  const auto t0 = Clock::now();
  server.stop();
  EXPECT_LT(Clock::now() - t0, 2s);
  EXPECT_EQ(server.stats().clients, 0);
  // The client is told (EOS or a closed connection), not left waiting for frames.
  while (client.next(100ms)) {
  }
  EXPECT_TRUE(eventually([&] { return !client.ended().empty(); }, 10s));
  server.stop();  // idempotent
}

TEST(RtspServer, DropsWithoutBlockingWhenNobodyWatches) {
  RtspServer server(ephemeral());
  auto frame = std::make_shared<const ImageRGB8>(test_frame(1));
  const auto t0 = Clock::now();
  for (int i = 0; i < 100; ++i) server.push(frame, monotonic_now_ns());
  EXPECT_LT(Clock::now() - t0, 100ms);
  const RtspServerStats s = server.stats();
  EXPECT_EQ(s.frames_pushed, 100u);
  EXPECT_EQ(s.media_created, 0u) << "nothing is encoded for nobody";
  EXPECT_EQ(s.dropped_no_client, 100u);
  EXPECT_EQ(s.frames_sent, 0u);
  EXPECT_EQ(s.clients, 0);
}

TEST(RtspServer, DropsWhenTheEncoderIsBehind) {
  RtspServer server(ephemeral());
  Feeder feeder(server);
  RtspTestClient client(server.url());
  ASSERT_TRUE(client.next(10s).has_value()) << client.ended();
  // A burst far faster than any encoder: the appsrc holds two frames, the rest are dropped
  // and counted, and push() still returns at once.
  auto frame = std::make_shared<const ImageRGB8>(test_frame(7));
  const auto before = server.stats();
  const auto t0 = Clock::now();
  for (int i = 0; i < 50; ++i) server.push(frame, monotonic_now_ns());
  EXPECT_LT(Clock::now() - t0, 50ms);
  const auto after = server.stats();
  EXPECT_GT(after.dropped_queue_full, before.dropped_queue_full);
  EXPECT_LE(after.frames_sent - before.frames_sent, 50u);
}

TEST(RtspServer, PortInUseIsAClearError) {
  RtspServer first(ephemeral());
  RtspServerConfig same = ephemeral();
  same.port = first.port();
  expect_error(same, "cannot listen on 127.0.0.1:" + std::to_string(first.port()));
}

TEST(RtspServer, BadConfigurationIsAClearError) {
  for (const char* path : {"probeless", "/", "", "/a b", "/../x", "/x/", "/x//y", "/x?y=1"}) {
    SCOPED_TRACE(path);
    RtspServerConfig c = ephemeral();
    c.path = path;
    expect_error(c, "path");
  }
  RtspServerConfig c = ephemeral();
  c.encoder = "h265";
  expect_error(c, "not one of auto, v4l2h264enc, x264enc");
  c = ephemeral();
  c.bitrate_kbps = 0;
  expect_error(c, "bitrate_kbps");
  c = ephemeral();
  c.keyframe_interval = 0;
  expect_error(c, "keyframe_interval");
  c = ephemeral();
  c.framerate = 0;
  expect_error(c, "framerate");
  c = ephemeral();
  c.address = "192.0.2.1";  // TEST-NET-1 (RFC 5737): on no interface of this machine
  expect_error(c, "cannot listen on 192.0.2.1");
  EXPECT_NO_THROW(check_rtsp_path("/probeless"));
  EXPECT_NO_THROW(check_rtsp_path("/cam/composite-1.h264"));
}

// There is no V4L2 encoder on the development machine or CI: asking for it by name must
// say so and name what provides it, not fall back silently.
TEST(RtspServer, AMissingEncoderNamesThePackage) {
  gst::ensure_gstreamer();
  auto factory = gst::ElementFactory::adopt(gst_element_factory_find("v4l2h264enc"));
  if (factory) GTEST_SKIP() << "this machine has a V4L2 H.264 encoder";
  RtspServerConfig c = ephemeral();
  c.encoder = "v4l2h264enc";
  expect_error(c, "gstreamer1.0-plugins-good");
  EXPECT_EQ(choose_h264_encoder("auto"), "x264enc");
}

}  // namespace
}  // namespace probeless

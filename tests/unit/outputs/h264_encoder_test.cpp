// The service's one H.264 encoder (app/outputs/h264_encoder.hpp): a frame pushed by both
// outputs is encoded once, its access unit reaches every subscriber with its capture time,
// keyframe requests in a burst are coalesced; and with RTSP and WebRTC both on, built as the
// service builds them, an RTSP player and a WHEP client decode that one encoder's stream at
// the same time.
#include "app/outputs/h264_encoder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "app/outputs/http_server.hpp"
#include "app/outputs/webrtc_output.hpp"
#include "app/pipeline/output_factory.hpp"
#include "core/capture_stamp.hpp"
#include "eventually.hpp"
#include "lab/bench/whep_receiver.hpp"
#include "rtsp_test_client.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

using testing::eventually;

// What a subscriber saw.
struct Seen {
  std::mutex mutex;
  std::vector<TimestampNs> capture_ns;
  std::vector<bool> keyframe;
  std::size_t size() {
    std::lock_guard lock(mutex);
    return capture_ns.size();
  }
  H264Encoder::Subscriber subscriber() {
    return [this](const H264AccessUnit& unit) {
      std::lock_guard lock(mutex);
      capture_ns.push_back(unit.capture_ns);
      keyframe.push_back(unit.keyframe);
    };
  }
};

TEST(H264Encoder, AFramePushedByTwoOutputsIsEncodedOnce) {
  RtspServerConfig config;
  config.max_queued_frames = 30;  // a starved encoder thread (a loaded host) drops no frame here
  H264Encoder encoder(config);
  Seen seen;
  auto subscription = encoder.subscribe(seen.subscriber());
  std::vector<TimestampNs> pushed;
  for (int i = 0; i < 10; ++i) {
    auto frame = std::make_shared<const ImageRGB8>(testing::gradient_image(320, 240, i));
    const TimestampNs t = monotonic_now_ns();
    pushed.push_back(t);
    EXPECT_EQ(encoder.push(frame, t), H264Encoder::Fed::Sent);
    EXPECT_EQ(encoder.push(frame, t), H264Encoder::Fed::Sent) << "the other output's push";
    std::this_thread::sleep_for(33ms);
  }
  ASSERT_TRUE(eventually([&] { return seen.size() == 10; })) << seen.size() << " access units";
  H264EncoderStats s = encoder.stats();
  EXPECT_EQ(s.frames_in, 10u);
  EXPECT_EQ(s.frames_shared, 10u);
  EXPECT_EQ(s.access_units, 10u);
  EXPECT_EQ(s.subscribers, 1);
  EXPECT_EQ(seen.capture_ns, pushed) << "each access unit carries its frame's capture time";
  EXPECT_TRUE(seen.keyframe.front()) << "a stream starts at a keyframe";

  // The same picture at a new time is a new frame (a still scene); after reset() the
  // subscriber is called no more.
  subscription.reset();
  EXPECT_EQ(encoder.stats().subscribers, 0);
  auto still = std::make_shared<const ImageRGB8>(testing::gradient_image(320, 240));
  EXPECT_EQ(encoder.push(still, monotonic_now_ns()), H264Encoder::Fed::Sent);
  std::this_thread::sleep_for(40ms);
  EXPECT_EQ(encoder.push(still, monotonic_now_ns()), H264Encoder::Fed::Sent);
  ASSERT_TRUE(eventually([&] { return encoder.stats().access_units == 12; }));
  EXPECT_EQ(seen.size(), 10u);
}

TEST(H264Encoder, KeyframeRequestsInABurstMakeAtMostTwo) {
  H264Encoder encoder(RtspServerConfig{});  // a keyframe every 30 frames at most
  Seen seen;
  auto subscription = encoder.subscribe(seen.subscriber());
  // One still picture: x264 at ultrafast has no scene-cut keyframes to confuse the count.
  auto still = std::make_shared<const ImageRGB8>(testing::gradient_image(320, 240));
  auto push_for = [&](std::chrono::milliseconds duration) {
    for (const auto end = Clock::now() + duration; Clock::now() < end;) {
      (void)encoder.push(still, monotonic_now_ns());
      std::this_thread::sleep_for(33ms);
    }
  };
  push_for(150ms);
  EXPECT_TRUE(encoder.request_keyframe()) << "forced at once";
  EXPECT_TRUE(encoder.request_keyframe()) << "within 250 ms: kept for later, not dropped";
  EXPECT_FALSE(encoder.request_keyframe()) << "answered by the pending one";
  push_for(450ms);
  ASSERT_TRUE(eventually([&] { return seen.size() == encoder.stats().frames_in; }));
  std::lock_guard lock(seen.mutex);
  ASSERT_LT(seen.keyframe.size(), 30u) << "the periodic keyframe would be counted";
  EXPECT_EQ(std::count(seen.keyframe.begin(), seen.keyframe.end(), true), 3)
      << "the first, the forced and the pending one";
  EXPECT_EQ(encoder.stats().keyframes_forced, 2u);
}

// Decodes for `duration`; the capture times read back from the pictures' stamps.
template <typename Next>
std::vector<TimestampNs> decode_stamps(Next next, std::chrono::milliseconds duration) {
  std::vector<TimestampNs> stamps;
  for (const auto end = Clock::now() + duration; Clock::now() < end;) {
    std::optional<ImageRGB8> image = next();
    if (!image) continue;
    const StampReading r = read_capture_stamp(*image);
    if (r.result == StampRead::Ok) stamps.push_back(unwrap_stamp(r.micros, monotonic_now_ns()));
  }
  return stamps;
}

TEST(RtspAndWebRtc, ShareOneEncoderThatAPlayerAndAWhepClientDecodeAtOnce) {
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    GTEST_SKIP() << "no WebRTC in this GStreamer: " << missing;
  ServiceConfig config;
  config.rtsp.enabled = true;
  config.rtsp.port = 0;
  config.rtsp.path = "/shared";
  config.webrtc.enabled = true;
  SharedOutputParts shared;  // as Pipeline::open_outputs() builds them
  std::shared_ptr<Output> rtsp_output = make_output("rtsp", config, {}, &shared);
  std::shared_ptr<Output> webrtc_output = make_output("webrtc", config, {}, &shared);
  auto rtsp = std::dynamic_pointer_cast<RtspServer>(rtsp_output);
  auto webrtc = std::dynamic_pointer_cast<WebRtcOutput>(webrtc_output);
  ASSERT_TRUE(rtsp && webrtc);
  ASSERT_NE(shared.h264, nullptr);
  EXPECT_EQ(rtsp->encoder(), shared.h264);
  EXPECT_EQ(webrtc->encoder(), shared.h264) << "one encoder object for both outputs";

  HttpServerConfig http_config;
  http_config.port = 0;
  HttpServer http(http_config);
  http.set_whep(webrtc);

  // The pipeline's output thread: every composite offered to both outputs, stamped with
  // its capture time so that a decoded picture says which composite it was.
  std::mutex offered_mutex;
  std::set<TimestampNs> offered_us;  // capture times in microseconds, as the stamp has them
  std::jthread feeder([&](std::stop_token stop) {
    for (int i = 0; !stop.stop_requested(); ++i) {
      ImageRGB8 image = testing::gradient_image(320, 240, i);
      OutputFrame out;
      out.timestamp_ns = monotonic_now_ns();
      draw_capture_stamp(image, out.timestamp_ns);
      out.colour = std::make_shared<const ImageRGB8>(std::move(image));
      {
        std::lock_guard lock(offered_mutex);
        offered_us.insert(out.timestamp_ns / 1000);
      }
      rtsp_output->offer(out);
      webrtc_output->offer(out);
      std::this_thread::sleep_for(33ms);
    }
  });

  testing::RtspTestClient player(rtsp->url(), "tcp");
  lab::WhepReceiver browser(http.port());
  ASSERT_TRUE(player.next(10s).has_value()) << player.ended();
  bool browser_started = false;  // next() returns at once until the stream's pad appears
  for (const auto end = Clock::now() + 10s; !browser_started && Clock::now() < end;)
    browser_started = browser.next(500ms).has_value();
  ASSERT_TRUE(browser_started) << "the WHEP client decoded nothing";
  const H264EncoderStats before = shared.h264->stats();
  std::vector<TimestampNs> by_rtsp;
  std::jthread rtsp_side([&] {
    by_rtsp = decode_stamps(
        [&]() -> std::optional<ImageRGB8> {
          auto f = player.next(500ms);
          return f ? std::optional(std::move(f->image)) : std::nullopt;
        },
        2s);
  });
  const std::vector<TimestampNs> by_webrtc = decode_stamps(
      [&]() -> std::optional<ImageRGB8> {
        auto f = browser.next(500ms);
        return f ? std::optional(std::move(f->image)) : std::nullopt;
      },
      2s);
  rtsp_side.join();
  const H264EncoderStats after = shared.h264->stats();
  feeder.request_stop();
  feeder.join();

  std::printf(
      "[ shared ] in 2 s: %zu frames decoded over RTSP, %zu over WebRTC; the one encoder took "
      "%llu frames (%llu pushed again by the second output) and made %llu access units\n",
      by_rtsp.size(), by_webrtc.size(),
      static_cast<unsigned long long>(after.frames_in - before.frames_in),
      static_cast<unsigned long long>(after.frames_shared - before.frames_shared),
      static_cast<unsigned long long>(after.access_units - before.access_units));
  // At 30 Hz for 2 s both decode most frames, each one a composite that was offered (the
  // player may count more: what queued while the WHEP client connected).
  EXPECT_GE(by_rtsp.size(), 30u);  // ~60 on a quiet host; room for a loaded one
  EXPECT_GE(by_webrtc.size(), 30u);
  {
    std::lock_guard lock(offered_mutex);
    for (const TimestampNs t : by_rtsp) EXPECT_TRUE(offered_us.contains(t / 1000)) << t;
    for (const TimestampNs t : by_webrtc) EXPECT_TRUE(offered_us.contains(t / 1000)) << t;
  }
  EXPECT_TRUE(std::is_sorted(by_rtsp.begin(), by_rtsp.end(), std::less_equal<>()))
      << "each composite once, in order";
  EXPECT_TRUE(std::is_sorted(by_webrtc.begin(), by_webrtc.end(), std::less_equal<>()));
  // Offered twice each (once per output), encoded once each.
  const auto frames_in = after.frames_in - before.frames_in;
  const auto shared_pushes = after.frames_shared - before.frames_shared;
  EXPECT_GE(frames_in, 40u);
  EXPECT_GE(shared_pushes + 2, frames_in) << "the second output's push was encoded again";
  EXPECT_LE(after.access_units - before.access_units, frames_in + 2);
  EXPECT_EQ(after.subscribers, 2);
  nlohmann::json rtsp_status, webrtc_status;
  rtsp->add_status(rtsp_status);
  webrtc->add_status(webrtc_status);
  EXPECT_EQ(rtsp_status["h264"]["subscribers"], 2);
  EXPECT_EQ(webrtc_status["h264"]["subscribers"], 2);
  EXPECT_GT(rtsp_status["rtsp"]["access_units_sent"], 30);
  EXPECT_GT(webrtc_status["webrtc"]["frames_encoded"], 30);

  // Either output may stop first: the other goes on until it stops too, and nothing calls
  // into a stopped one (the ASan preset would say).
  rtsp->stop();
  EXPECT_EQ(shared.h264->stats().subscribers, 1);
  webrtc->stop();
  http.stop();
  EXPECT_EQ(shared.h264->stats().subscribers, 0);
}

}  // namespace
}  // namespace probeless

#pragma once
// The service's outputs built from its config by name (app/outputs/output.hpp).
#include <memory>
#include <string_view>

#include "app/outputs/output.hpp"
#include "app/pipeline/service_config.hpp"

namespace probeless {

// The names make_output() knows, in the order the pipeline builds them.
inline constexpr std::string_view kOutputNames[] = {"http", "rtsp", "webrtc", "files", "display"};

class H264Encoder;

// What the outputs of one service share: the H.264 encoder of RTSP and WebRTC (issue #22: one
// encoder, whatever streams it), made from [rtsp] by the first of them built.
struct SharedOutputParts {
  std::shared_ptr<H264Encoder> h264;
};

// The output called `name` (one of kOutputNames) from its part of the service config, or
// null when that part is off; `status` is what the HTTP server serves on GET /status. The
// outputs made with the same `shared` share its parts; without, each has its own.
// Throws what the output's constructor throws (a port in use, no H.264 encoder, a directory
// that cannot be made, a bad mode); std::invalid_argument for a name it does not know.
std::unique_ptr<Output> make_output(std::string_view name, const ServiceConfig& config,
                                    HttpServer::StatusCallback status = {},
                                    SharedOutputParts* shared = nullptr);

}  // namespace probeless

#include "app/pipeline/output_factory.hpp"

#include <stdexcept>
#include <string>

#include "app/outputs/h264_encoder.hpp"

namespace probeless {
namespace {

// The service's encoder, made by the first output that needs it; null without `shared` (the
// output makes its own).
std::shared_ptr<H264Encoder> shared_h264(const ServiceConfig& config, SharedOutputParts* shared) {
  if (!shared) return nullptr;
  if (!shared->h264) shared->h264 = std::make_shared<H264Encoder>(config.rtsp);
  return shared->h264;
}

}  // namespace

std::unique_ptr<Output> make_output(std::string_view name, const ServiceConfig& config,
                                    HttpServer::StatusCallback status, SharedOutputParts* shared) {
  if (name == "http") {  // throws HttpServerError: the address cannot be bound
    if (!config.http.enabled) return nullptr;
    return std::make_unique<HttpServer>(config.http, std::move(status));
  }
  if (name == "rtsp") {  // throws RtspServerError: port in use, no encoder
    if (!config.rtsp.enabled) return nullptr;
    return std::make_unique<RtspServer>(config.rtsp, shared_h264(config, shared));
  }
  if (name == "webrtc") {  // throws WebRtcError: a plugin or the encoder missing
    if (!config.webrtc.enabled) return nullptr;
    if (!shared) return std::make_unique<WebRtcOutput>(config.webrtc, config.rtsp);
    if (!shared->h264) shared->h264 = WebRtcOutput::make_encoder(config.rtsp);
    return std::make_unique<WebRtcOutput>(config.webrtc, shared->h264);
  }
  if (name == "files") {  // throws filesystem_error: the directory cannot be made
    if (config.files.dir.empty()) return nullptr;
    return std::make_unique<FileOutput>(config.files);
  }
  if (name == "display") {  // a bad mode throws; a missing screen is retried, not fatal
    if (!config.display.enabled) return nullptr;
    return std::make_unique<KmsDisplay>(config.display);
  }
  throw std::invalid_argument("no output called '" + std::string(name) + "'");
}

}  // namespace probeless

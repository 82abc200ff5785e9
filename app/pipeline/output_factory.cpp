#include "app/pipeline/output_factory.hpp"

#include <stdexcept>
#include <string>

namespace probeless {

std::unique_ptr<Output> make_output(std::string_view name, const ServiceConfig& config,
                                    HttpServer::StatusCallback status) {
  if (name == "http") {  // throws HttpServerError: the address cannot be bound
    if (!config.http.enabled) return nullptr;
    return std::make_unique<HttpServer>(config.http, std::move(status));
  }
  if (name == "rtsp") {  // throws RtspServerError: port in use, no encoder
    if (!config.rtsp.enabled) return nullptr;
    return std::make_unique<RtspServer>(config.rtsp);
  }
  if (name == "webrtc") {  // throws WebRtcError: a plugin or the encoder missing
    if (!config.webrtc.enabled) return nullptr;
    return std::make_unique<WebRtcOutput>(config.webrtc, config.rtsp);
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

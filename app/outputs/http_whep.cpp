// WHEP on the HTTP server (docs/outputs.md "WebRTC (WHEP)"): POST an SDP offer to /whep (or
// mediamtx's /<path>/whep), get 201 with the answer and the session's resource URL in
// Location; DELETE that URL ends the session; OPTIONS answers a CORS preflight. The answer is
// made on the WebRTC output's thread (ICE gathering takes a moment): the request waits here,
// the event loop goes on, and the output's callback wakes the loop through a mailbox that
// outlives the server.
#include <event2/buffer.h>
#include <event2/event.h>
#include <event2/http.h>

#include <algorithm>
#include <cctype>
#include <string>

#include "app/outputs/http_server_impl.hpp"
#include "app/outputs/whep_offer.hpp"

namespace probeless {
namespace {

constexpr const char* kWhepAllowed = "OPTIONS, POST";
constexpr const char* kResourceAllowed = "OPTIONS, DELETE";

void on_whep_closed_cb(evhttp_connection*, void* arg) {
  auto* pending = static_cast<PendingWhep*>(arg);
  pending->server->whep_connection_closed(*pending);
}

// "application/sdp", any case, parameters after ';' ignored.
bool is_sdp_type(const char* content_type) {
  if (!content_type) return false;
  std::string type(content_type);
  type = type.substr(0, type.find(';'));
  while (!type.empty() && std::isspace(static_cast<unsigned char>(type.back()))) type.pop_back();
  std::transform(type.begin(), type.end(), type.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return type == "application/sdp";
}

}  // namespace

void HttpServer::Impl::set_whep(std::shared_ptr<WhepEndpoint> endpoint) {
  std::lock_guard lock(whep_mutex);
  whep = std::move(endpoint);
}

std::shared_ptr<WhepEndpoint> HttpServer::Impl::whep_endpoint() {
  std::lock_guard lock(whep_mutex);
  return whep;
}

void HttpServer::Impl::serve_whep(evhttp_request* req, bool resource, std::string_view path) {
  const evhttp_cmd_type method = evhttp_request_get_command(req);
  evkeyvalq* out = evhttp_request_get_output_headers(req);
  const char* allowed = resource ? kResourceAllowed : kWhepAllowed;
  if (method == EVHTTP_REQ_OPTIONS) {
    evhttp_add_header(out, "Allow", allowed);
    evhttp_add_header(out, "Access-Control-Allow-Methods", allowed);
    evhttp_add_header(out, "Access-Control-Allow-Headers", "Authorization, Content-Type");
    evhttp_add_header(out, "Access-Control-Expose-Headers", "Location");
    if (!resource) evhttp_add_header(out, "Accept-Post", "application/sdp");
    send_text(req, HTTP_OK, "OK", "");
    return;
  }
  const bool wanted = resource ? method == EVHTTP_REQ_DELETE : method == EVHTTP_REQ_POST;
  if (!wanted) {
    // PATCH (trickle ICE) included: the answer already carries every candidate (WHEP lets a
    // server without trickle answer 405).
    evhttp_add_header(out, "Allow", allowed);
    send_text(req, 405, "Method Not Allowed",
              std::string("only ") + allowed + " are served here\n");
    return;
  }
  const std::shared_ptr<WhepEndpoint> endpoint = whep_endpoint();
  if (!endpoint) {
    send_text(req, HTTP_NOTFOUND, "Not Found",
              "WebRTC is off on this appliance ([webrtc] enabled = false)\n");
    return;
  }
  if (resource) {
    const std::string_view id = path.substr(path.rfind('/') + 1);
    if (endpoint->close_session(id))
      send_text(req, HTTP_OK, "OK", "");
    else
      send_text(req, HTTP_NOTFOUND, "Not Found", "no WebRTC session " + std::string(id) + "\n");
    return;
  }
  // The body was bounded by evhttp_set_max_body_size (kMaxWhepOfferBytes): a larger
  // Content-Length got 413 from libevent before a byte of it was read.
  if (!is_sdp_type(evhttp_find_header(evhttp_request_get_input_headers(req), "Content-Type"))) {
    send_text(req, 415, "Unsupported Media Type",
              "a WHEP offer is sent with Content-Type: application/sdp\n");
    return;
  }
  evbuffer* in = evhttp_request_get_input_buffer(req);
  const std::size_t length = evbuffer_get_length(in);
  if (length == 0) {
    send_text(req, HTTP_BADREQUEST, "Bad Request", "bad offer: empty offer\n");
    return;
  }
  if (length > kMaxWhepOfferBytes) {
    send_text(req, 413, "Payload Too Large", "bad offer: offer too large\n");
    return;
  }
  std::string sdp(length, '\0');
  evbuffer_copyout(in, sdp.data(), length);
  // Cheap checks here, so that garbage never reaches the output's queue.
  try {
    (void)choose_whep_format(sdp);
  } catch (const WhepOfferError& e) {
    send_text(req, HTTP_BADREQUEST, "Bad Request", std::string("bad offer: ") + e.what() + "\n");
    return;
  }
  evhttp_connection* conn = evhttp_request_get_connection(req);
  if (conn == nullptr) return;
  const std::uint64_t key = ++next_whep;
  auto pending = std::make_unique<PendingWhep>();
  pending->server = this;
  pending->key = key;
  pending->request = req;
  pending->location_base = std::string(path);
  evhttp_connection_set_closecb(conn, on_whep_closed_cb, pending.get());
  whep_pending.emplace(key, std::move(pending));
  endpoint->offer(std::move(sdp), [mailbox = whep_mailbox, key](WhepAnswer answer) {
    std::lock_guard lock(mailbox->mutex);
    if (mailbox->wake == nullptr) return;  // the server has stopped
    mailbox->done.emplace_back(key, std::move(answer));
    event_active(mailbox->wake, EV_READ, 0);
  });
}

void HttpServer::Impl::whep_connection_closed(PendingWhep& pending) {
  // A request detached from its failed connection is ours to free; one still attached is
  // freed by libevent right after this callback.
  if (pending.request && evhttp_request_get_connection(pending.request) == nullptr)
    evhttp_request_free(pending.request);
  pending.request = nullptr;
}

void HttpServer::Impl::on_whep_done() {
  std::vector<std::pair<std::uint64_t, WhepAnswer>> done;
  {
    std::lock_guard lock(whep_mailbox->mutex);
    done.swap(whep_mailbox->done);
  }
  for (auto& [key, answer] : done) {
    auto it = whep_pending.find(key);
    if (it == whep_pending.end()) continue;
    std::unique_ptr<PendingWhep> pending = std::move(it->second);
    whep_pending.erase(it);
    evhttp_request* req = pending->request;
    if (req == nullptr) {  // the client left while we answered: nobody will use the session
      if (answer.status == 201)
        if (auto endpoint = whep_endpoint()) endpoint->close_session(answer.session_id);
      continue;
    }
    if (evhttp_connection* conn = evhttp_request_get_connection(req))
      evhttp_connection_set_closecb(conn, nullptr, nullptr);
    if (answer.status != 201) {
      const char* reason = answer.status == 400   ? "Bad Request"
                           : answer.status == 503 ? "Service Unavailable"
                                                  : "Internal Server Error";
      if (answer.status == 503)
        evhttp_add_header(evhttp_request_get_output_headers(req), "Retry-After", "5");
      send_text(req, answer.status, reason, answer.error + "\n");
      continue;
    }
    evkeyvalq* out = evhttp_request_get_output_headers(req);
    evhttp_add_header(out, "Location", (pending->location_base + "/" + answer.session_id).c_str());
    evhttp_add_header(out, "Access-Control-Expose-Headers", "Location");
    evbuffer* body = evbuffer_new();
    evbuffer_add(body, answer.sdp.data(), answer.sdp.size());
    send_body(req, 201, "Created", "application/sdp", body);
    evbuffer_free(body);
  }
}

void HttpServer::Impl::drop_pending_whep() {
  {
    std::lock_guard lock(whep_mailbox->mutex);
    whep_mailbox->wake = nullptr;
    whep_mailbox->done.clear();
  }
  for (auto& [key, pending] : whep_pending) {
    if (pending->request == nullptr) continue;
    if (evhttp_connection* conn = evhttp_request_get_connection(pending->request))
      evhttp_connection_set_closecb(conn, nullptr, nullptr);  // evhttp_free() frees it
    else
      evhttp_request_free(pending->request);
  }
  whep_pending.clear();
}

void HttpServer::set_whep(std::shared_ptr<WhepEndpoint> endpoint) {
  impl_->set_whep(std::move(endpoint));
}

}  // namespace probeless

#include "operator_client/web/web_server.h"

#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <atomic>
#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include "common/log/log.h"
#include "operator_client/web/client_outbox.h"
#include "operator_client/web/http_target.h"
#include "operator_client/web/web_assets.h"

namespace mostar::web {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

bool WebServerOptions::IsValid(std::string* error) const {
  if (cert_file.empty() || key_file.empty()) {
    *error = "a TLS certificate and key are required (--cert, --key)";
    return false;
  }
  if (!tokens && client_ca_file.empty()) {
    *error = "no login: give a tokens file (--tokens) and/or a client CA (--client-ca)";
    return false;
  }
  if (port < 0 || port > 65535) {
    *error = "port must be in [0, 65535] (got " + std::to_string(port) + ")";
    return false;
  }
  if (max_browsers < 1) {
    *error = "max_browsers must be >= 1";
    return false;
  }
  if (request_timeout <= Duration(0) || write_timeout <= Duration(0) ||
      idle_timeout <= Duration(0)) {
    *error = "timeouts must be > 0";
    return false;
  }
  return true;
}

namespace {

struct Counters {
  std::atomic<uint64_t> connections{0}, tls_failures{0}, http_requests{0}, http_bad_requests{0},
      http_timeouts{0}, not_found{0}, token_refused{0}, over_capacity{0}, browsers_opened{0},
      browsers_open{0}, bad_frames{0}, client_messages{0}, stalled{0}, idle_closed{0}, aborted{0},
      frames_written{0}, frames_dropped{0}, huds_written{0};
};

std::chrono::steady_clock::duration Steady(Duration d) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(d);
}

// The CN of the peer's certificate, empty when there is none.
std::string PeerCommonName(TlsStream& stream) {
  X509* cert = SSL_get_peer_certificate(stream.native_handle());
  if (cert == nullptr) return "";
  char cn[256] = {0};
  X509_NAME_get_text_by_NID(X509_get_subject_name(cert), NID_commonName, cn, sizeof cn);
  X509_free(cert);
  return cn;
}

template <class Body>
void SecurityHeaders(http::response<Body>* response) {
  response->set(http::field::server, "mostar_web");
  response->set(http::field::cache_control, "no-store");
  response->set("X-Content-Type-Options", "nosniff");
  response->set("X-Frame-Options", "DENY");
  response->set("Referrer-Policy", "no-referrer");
  response->set("Strict-Transport-Security", "max-age=31536000");
  response->set("Content-Security-Policy",
                "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' blob:; "
                "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'");
}

}  // namespace

class WsSession;

class WebServer::Impl {
 public:
  Impl(const WebServerOptions& options, std::function<std::string()> extra_stats)
      : options_(options),
        extra_stats_(std::move(extra_stats)),
        tls_(ssl::context::tls_server),
        acceptor_(io_) {}

  bool Init(std::string* error);
  void Accept();
  void Remove(const WsSession* session);
  void Add(std::shared_ptr<WsSession> session);
  void Broadcast(const OutMessage& left_only, const OutMessage& both_eyes);
  bool AtCapacity() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return sessions_.size() >= static_cast<size_t>(options_.max_browsers);
  }
  // The observer's name when the request may have the stream or the statistics.
  std::optional<std::string> Authorize(const HttpTarget& target, const std::string& cert_cn) const;
  std::string StatsJson() const;

  const WebServerOptions options_;
  std::function<std::string()> extra_stats_;
  net::io_context io_;
  ssl::context tls_;
  tcp::acceptor acceptor_;
  Counters counters_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<WsSession>> sessions_;
  std::atomic<int> both_eyes_wanted_{0};
};

// One browser's WebSocket: a read loop (only to see close, pings and bad frames) and the write
// chain driven by its ClientOutbox. Runs on the network thread only.
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(WebServer::Impl* server, TlsStream&& stream, std::string name, bool both_eyes)
      : server_(server),
        ws_(std::move(stream)),
        write_timer_(ws_.get_executor()),
        name_(std::move(name)),
        both_eyes_(both_eyes) {}

  bool both_eyes() const { return both_eyes_; }

  void Start(http::request<http::string_body> request) {
    beast::get_lowest_layer(ws_).expires_never();  // the websocket stream has its own timeouts
    websocket::stream_base::timeout timeout;
    timeout.handshake_timeout = Steady(server_->options_.request_timeout);
    timeout.idle_timeout = Steady(server_->options_.idle_timeout);
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& r) { r.set(http::field::server, "mostar_web"); }));
    ws_.read_message_max(kMaxClientMessageBytes);
    // A close frame from the browser (with or without a status code) is an orderly end.
    ws_.control_callback([this](websocket::frame_type kind, beast::string_view) {
      if (kind == websocket::frame_type::close) peer_closed_ = true;
    });
    ws_.auto_fragment(false);
    ws_.async_accept(request,
                     [self = shared_from_this()](beast::error_code ec) { self->OnAccept(ec); });
  }

  void Offer(const OutMessage& message) {
    if (closed_) return;
    const OutboxCounters before = outbox_.counters();
    std::optional<OutMessage> now = outbox_.Offer(message);
    if (outbox_.counters().frames_dropped > before.frames_dropped) {
      ++server_->counters_.frames_dropped;
    }
    if (now) Write(std::move(*now));
  }

 private:
  void OnAccept(beast::error_code ec) {
    if (ec) {
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "web: WebSocket handshake of '" << name_ << "' failed: " << ec.message();
      ++server_->counters_.http_bad_requests;
      return;
    }
    ++server_->counters_.browsers_opened;
    ++server_->counters_.browsers_open;
    MOSTAR_LOG(INFO) << "web: browser '" << name_ << "' connected"
                     << (both_eyes_ ? " (both eyes)" : "");
    server_->Add(shared_from_this());
    Read();
  }

  void Read() {
    ws_.async_read(read_buffer_,
                   [self = shared_from_this()](beast::error_code ec, size_t) { self->OnRead(ec); });
  }

  void OnRead(beast::error_code ec) {
    if (!ec) {
      ++server_->counters_.client_messages;  // the page sends nothing we act on
      read_buffer_.consume(read_buffer_.size());
      Read();
      return;
    }
    // Over TLS Beast reports a bad frame as the error of the teardown that follows it (the
    // browser's reply to our close frame arrives after our close_notify): the stream failed
    // the connection when it sent its close_notify without having received a close frame.
    const bool failed_by_stream =
        !peer_closed_ &&
        (SSL_get_shutdown(ws_.next_layer().native_handle()) & SSL_SENT_SHUTDOWN) != 0 &&
        ec != websocket::error::closed;
    if (ec == websocket::condition::protocol_violation || ec == websocket::error::message_too_big ||
        ec == websocket::error::buffer_overflow || failed_by_stream) {
      ++server_->counters_.bad_frames;
      MOSTAR_LOG_EVERY_SEC(WARNING, 1) << "web: bad WebSocket frame from '" << name_
                                       << "': " << ec.message() << "; disconnected";
    } else if (ec == beast::error::timeout) {
      ++server_->counters_.idle_closed;
      MOSTAR_LOG_EVERY_SEC(WARNING, 1) << "web: browser '" << name_ << "' silent; disconnected";
    } else if (!peer_closed_ && ec != websocket::error::closed && ec != net::error::eof &&
               ec != net::error::operation_aborted) {
      // Reset, truncated TLS, data after close: also a peer that sent a bad frame and dropped
      // the connection before the closing handshake (Beast then reports the transport error).
      ++server_->counters_.aborted;
    }
    Close(ec.message());
  }

  void Write(OutMessage message) {
    in_flight_ = std::move(message);
    const bool frame = in_flight_.kind == MessageKind::kFrame;
    ws_.binary(frame);
    write_timer_.expires_after(Steady(server_->options_.write_timeout));
    write_timer_.async_wait([weak = weak_from_this()](beast::error_code ec) {
      if (ec == net::error::operation_aborted) return;
      if (auto self = weak.lock()) self->OnWriteStalled();
    });
    ws_.async_write(
        net::buffer(*in_flight_.bytes),
        [self = shared_from_this()](beast::error_code ec, size_t) { self->OnWritten(ec); });
  }

  void OnWriteStalled() {
    if (closed_) return;
    ++server_->counters_.stalled;
    MOSTAR_LOG_EVERY_SEC(WARNING, 1) << "web: browser '" << name_
                                     << "' did not take a message within the write timeout; "
                                        "disconnected";
    Close("write timeout");
  }

  void OnWritten(beast::error_code ec) {
    write_timer_.cancel();
    if (ec) {
      // The read side ends the session and says why (a bad frame from the browser makes the
      // stream fail this write too); until then nothing more is written to this browser.
      return;
    }
    ++(in_flight_.kind == MessageKind::kFrame ? server_->counters_.frames_written
                                              : server_->counters_.huds_written);
    in_flight_.bytes.reset();
    if (closed_) return;
    if (std::optional<OutMessage> next = outbox_.Written()) Write(std::move(*next));
  }

  // Ends the session: the socket is closed at once (pending reads and writes complete with an
  // error); no closing handshake, which a stalled browser would not answer anyway.
  void Close(const std::string& why) {
    if (closed_) return;
    closed_ = true;
    write_timer_.cancel();
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).close();
    --server_->counters_.browsers_open;
    MOSTAR_LOG(INFO) << "web: browser '" << name_ << "' disconnected (" << why << ")";
    server_->Remove(this);
  }

  WebServer::Impl* server_;
  websocket::stream<TlsStream> ws_;
  net::steady_timer write_timer_;
  const std::string name_;
  const bool both_eyes_;
  beast::flat_buffer read_buffer_;
  ClientOutbox outbox_;
  OutMessage in_flight_;
  bool closed_ = false;
  bool peer_closed_ = false;  // the browser sent a close frame
};

// One TLS connection until it becomes a WebSocket or closes: TLS handshake, then HTTP requests
// (keep-alive), each bounded by request_timeout.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(WebServer::Impl* server, tcp::socket&& socket)
      : server_(server), stream_(std::move(socket), server->tls_) {}

  void Start() {
    beast::get_lowest_layer(stream_).expires_after(Steady(server_->options_.request_timeout));
    stream_.async_handshake(
        ssl::stream_base::server,
        [self = shared_from_this()](beast::error_code ec) { self->OnHandshake(ec); });
  }

 private:
  void OnHandshake(beast::error_code ec) {
    if (ec) {
      ++server_->counters_.tls_failures;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "web: TLS handshake failed: " << ec.message();
      return;
    }
    cert_cn_ = PeerCommonName(stream_);
    Read();
  }

  void Read() {
    parser_.emplace();
    parser_->header_limit(8192);
    parser_->body_limit(4096);
    beast::get_lowest_layer(stream_).expires_after(Steady(server_->options_.request_timeout));
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, size_t) { self->OnRead(ec); });
  }

  void OnRead(beast::error_code ec) {
    if (ec == http::error::end_of_stream || ec == net::ssl::error::stream_truncated) {
      Shutdown();
      return;
    }
    if (ec == beast::error::timeout) {
      // Between keep-alive requests this is an ordinary end; mid-request it is a slow client.
      if (parser_->got_some()) ++server_->counters_.http_timeouts;
      return;
    }
    if (ec) {
      ++server_->counters_.http_bad_requests;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "web: bad HTTP request: " << ec.message();
      return;
    }
    ++server_->counters_.http_requests;
    http::request<http::string_body> request = parser_->release();
    const beast::string_view raw_target = request.target();
    const std::optional<HttpTarget> target =
        ParseTarget(std::string_view(raw_target.data(), raw_target.size()));
    if (!target) {
      ++server_->counters_.http_bad_requests;
      Respond(request, http::status::bad_request, "bad request target\n", "text/plain");
      return;
    }
    if (target->path == "/ws") {
      Upgrade(std::move(request), *target);
      return;
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      ++server_->counters_.http_bad_requests;
      Respond(request, http::status::method_not_allowed, "GET only\n", "text/plain");
      return;
    }
    if (target->path == "/stats") {
      if (!server_->Authorize(*target, cert_cn_)) {
        Refuse(request, *target);
        return;
      }
      Respond(request, http::status::ok, server_->StatsJson(), "application/json");
      return;
    }
    if (const WebAsset* asset = FindAsset(target->path)) {
      Respond(request, http::status::ok,
              std::string(reinterpret_cast<const char*>(asset->data), asset->size),
              asset->content_type);
      return;
    }
    ++server_->counters_.not_found;
    Respond(request, http::status::not_found, "not found\n", "text/plain");
  }

  void Refuse(const http::request<http::string_body>& request, const HttpTarget& target) {
    ++server_->counters_.token_refused;
    MOSTAR_LOG_EVERY_SEC(WARNING, 1)
        << "web: refused " << target.path.substr(0, 32) << ": no valid token";
    Respond(request, http::status::unauthorized, "a valid token is required\n", "text/plain",
            /*close=*/true);
  }

  void Upgrade(http::request<http::string_body> request, const HttpTarget& target) {
    if (!websocket::is_upgrade(request)) {
      ++server_->counters_.http_bad_requests;
      Respond(request, http::status::bad_request, "WebSocket upgrade expected\n", "text/plain");
      return;
    }
    const std::optional<std::string> name = server_->Authorize(target, cert_cn_);
    if (!name) {
      Refuse(request, target);
      return;
    }
    if (server_->AtCapacity()) {
      ++server_->counters_.over_capacity;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "web: browser '" << *name << "' refused: " << server_->options_.max_browsers
          << " browsers already connected";
      Respond(request, http::status::service_unavailable, "too many browsers\n", "text/plain",
              /*close=*/true);
      return;
    }
    const auto eyes = target.query.find("eyes");
    const bool both_eyes = eyes != target.query.end() && eyes->second == "2";
    std::make_shared<WsSession>(server_, std::move(stream_), *name, both_eyes)
        ->Start(std::move(request));
  }

  void Respond(const http::request<http::string_body>& request, http::status status,
               std::string body, const std::string& content_type, bool close = false) {
    auto response = std::make_shared<http::response<http::string_body>>(status, request.version());
    SecurityHeaders(response.get());
    response->set(http::field::content_type, content_type);
    response->keep_alive(!close && request.keep_alive());
    if (request.method() != http::verb::head) response->body() = std::move(body);
    response->prepare_payload();
    beast::get_lowest_layer(stream_).expires_after(Steady(server_->options_.request_timeout));
    http::async_write(stream_, *response,
                      [self = shared_from_this(), response](beast::error_code ec, size_t) {
                        if (ec) return;
                        if (response->need_eof()) {
                          self->Shutdown();
                        } else {
                          self->Read();
                        }
                      });
  }

  void Shutdown() {
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(2));
    stream_.async_shutdown([self = shared_from_this()](beast::error_code) {});
  }

  WebServer::Impl* server_;
  TlsStream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::string cert_cn_;
};

bool WebServer::Impl::Init(std::string* error) {
  if (!options_.IsValid(error)) return false;
  beast::error_code ec;
  tls_.set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                   ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 |
                   ssl::context::single_dh_use);
  tls_.use_certificate_chain_file(options_.cert_file, ec);
  if (ec) {
    *error = options_.cert_file + ": " + ec.message();
    return false;
  }
  tls_.use_private_key_file(options_.key_file, ssl::context::pem, ec);
  if (ec) {
    *error = options_.key_file + ": " + ec.message();
    return false;
  }
  if (!options_.client_ca_file.empty()) {
    tls_.load_verify_file(options_.client_ca_file, ec);
    if (ec) {
      *error = options_.client_ca_file + ": " + ec.message();
      return false;
    }
    tls_.set_verify_mode(ssl::verify_peer | ssl::verify_fail_if_no_peer_cert);
  }
  const net::ip::address address = net::ip::make_address(options_.listen_address, ec);
  if (ec) {
    *error = "listen address '" + options_.listen_address + "': " + ec.message();
    return false;
  }
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(options_.port));
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    *error = "cannot listen on " + options_.listen_address + ":" + std::to_string(options_.port) +
             ": " + ec.message();
    return false;
  }
  return true;
}

void WebServer::Impl::Accept() {
  acceptor_.async_accept(io_, [this](beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted) return;
    if (!ec) {
      ++counters_.connections;
      beast::error_code ignored;
      socket.set_option(tcp::no_delay(true), ignored);
      std::make_shared<HttpSession>(this, std::move(socket))->Start();
    }
    Accept();
  });
}

void WebServer::Impl::Add(std::shared_ptr<WsSession> session) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (session->both_eyes()) ++both_eyes_wanted_;
  sessions_.push_back(std::move(session));
}

void WebServer::Impl::Remove(const WsSession* session) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end(); ++it) {
    if (it->get() != session) continue;
    if (session->both_eyes()) --both_eyes_wanted_;
    sessions_.erase(it);
    return;
  }
}

void WebServer::Impl::Broadcast(const OutMessage& left_only, const OutMessage& both_eyes) {
  std::vector<std::shared_ptr<WsSession>> sessions;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    sessions = sessions_;
  }
  for (const std::shared_ptr<WsSession>& s : sessions) {
    const OutMessage& message = s->both_eyes() && both_eyes.bytes ? both_eyes : left_only;
    net::post(io_, [s, message] { s->Offer(message); });
  }
}

std::optional<std::string> WebServer::Impl::Authorize(const HttpTarget& target,
                                                      const std::string& cert_cn) const {
  if (!options_.tokens) return cert_cn;  // the TLS handshake verified the certificate
  const auto token = target.query.find("token");
  if (token == target.query.end()) return std::nullopt;
  return options_.tokens->Check(token->second);
}

std::string WebServer::Impl::StatsJson() const {
  const Counters& c = counters_;
  std::string json = "{";
  auto add = [&json](const char* key, uint64_t v) {
    json += std::string("\"") + key + "\":" + std::to_string(v) + ",";
  };
  add("connections", c.connections);
  add("tls_failures", c.tls_failures);
  add("http_requests", c.http_requests);
  add("http_bad_requests", c.http_bad_requests);
  add("http_timeouts", c.http_timeouts);
  add("not_found", c.not_found);
  add("token_refused", c.token_refused);
  add("over_capacity", c.over_capacity);
  add("browsers_opened", c.browsers_opened);
  add("browsers_open", c.browsers_open);
  add("bad_frames", c.bad_frames);
  add("client_messages", c.client_messages);
  add("stalled", c.stalled);
  add("idle_closed", c.idle_closed);
  add("aborted", c.aborted);
  add("frames_written", c.frames_written);
  add("frames_dropped", c.frames_dropped);
  add("huds_written", c.huds_written);
  if (extra_stats_) json += extra_stats_();
  if (json.back() == ',') json.pop_back();
  return json + "}";
}

WebServer::WebServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

std::unique_ptr<WebServer> WebServer::Create(const WebServerOptions& options,
                                             std::function<std::string()> extra_stats,
                                             std::string* error) {
  auto impl = std::make_unique<Impl>(options, std::move(extra_stats));
  if (!impl->Init(error)) return nullptr;
  return std::unique_ptr<WebServer>(new WebServer(std::move(impl)));
}

WebServer::~WebServer() {
  if (impl_->thread_.joinable()) {
    net::post(impl_->io_, [this] {
      beast::error_code ignored;
      impl_->acceptor_.close(ignored);
    });
    impl_->io_.stop();
    impl_->thread_.join();
  }
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  impl_->sessions_.clear();
}

void WebServer::Start() {
  impl_->Accept();
  impl_->thread_ = std::thread([this] { impl_->io_.run(); });
}

int WebServer::port() const { return impl_->acceptor_.local_endpoint().port(); }

void WebServer::BroadcastFrame(const ComposedFrame& frame) {
  impl_->Broadcast({MessageKind::kFrame, frame.left_only}, {MessageKind::kFrame, frame.both_eyes});
}

void WebServer::BroadcastHud(std::shared_ptr<const std::string> hud_json) {
  const OutMessage message{MessageKind::kHud, std::move(hud_json)};
  impl_->Broadcast(message, message);
}

bool WebServer::WantsBothEyes() const { return impl_->both_eyes_wanted_.load() > 0; }

size_t WebServer::browsers() const {
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->sessions_.size();
}

WebServerStats WebServer::Stats() const {
  const Counters& c = impl_->counters_;
  WebServerStats s;
  s.connections = c.connections;
  s.tls_failures = c.tls_failures;
  s.http_requests = c.http_requests;
  s.http_bad_requests = c.http_bad_requests;
  s.http_timeouts = c.http_timeouts;
  s.not_found = c.not_found;
  s.token_refused = c.token_refused;
  s.over_capacity = c.over_capacity;
  s.browsers_opened = c.browsers_opened;
  s.browsers_open = c.browsers_open;
  s.bad_frames = c.bad_frames;
  s.client_messages = c.client_messages;
  s.stalled = c.stalled;
  s.idle_closed = c.idle_closed;
  s.aborted = c.aborted;
  s.frames_written = c.frames_written;
  s.frames_dropped = c.frames_dropped;
  s.huds_written = c.huds_written;
  return s;
}

std::string WebServer::StatsJson() const { return impl_->StatsJson(); }

}  // namespace mostar::web

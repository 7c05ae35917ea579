// mostar_web's network face: an HTTPS server (Boost.Beast over Boost.Asio and OpenSSL) that
// serves the page's files and /stats, and a WebSocket stream per browser at /ws. Knows nothing of
// DDS: the wiring hands it encoded frames and HUD messages (web_messages.h) to broadcast.
//
// Access: with a token table every /ws and /stats request must carry a valid `token` query
// parameter (else 401, counted); with a client CA every TLS handshake must present a certificate
// it signed (else the handshake fails, counted). The page's static files need neither.
//
// Every network wait is bounded: TLS handshake and each HTTP request by request_timeout, the
// WebSocket handshake by request_timeout, a WebSocket write by write_timeout (a browser that
// stops reading is disconnected and counted as stalled), an idle WebSocket by idle_timeout
// (pings keep live ones open). Malformed WebSocket frames and client messages larger than
// kMaxClientMessageBytes close that browser's connection and are counted. Each browser has a
// ClientOutbox: it gets the newest frame it can take and never delays the others.
//
// Threading: one network thread (Start() to the destructor) runs every connection; Broadcast*
// and Stats() may be called from any thread.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "operator_client/web/frame_composer.h"
#include "operator_client/web/token_table.h"

namespace mostar::web {

constexpr size_t kMaxClientMessageBytes = 4096;

struct WebServerOptions {
  std::string listen_address = "127.0.0.1";
  int port = 8443;                   // 0: any free port (see WebServer::port())
  std::string cert_file;             // PEM certificate (chain) of the server; required
  std::string key_file;              // PEM private key; required
  std::string client_ca_file;        // PEM CA: browsers must present a certificate it signed
  std::optional<TokenTable> tokens;  // browsers must present one of these tokens
  int max_browsers = 32;             // WebSocket connections beyond this get 503
  Duration request_timeout = std::chrono::seconds(10);
  Duration write_timeout = std::chrono::seconds(5);
  Duration idle_timeout = std::chrono::seconds(30);

  bool IsValid(std::string* error) const;
};

// Counters since start. All refusals are counted here and logged (rate-limited).
struct WebServerStats {
  uint64_t connections = 0;   // TCP connections accepted
  uint64_t tls_failures = 0;  // TLS handshakes that failed (incl. missing client cert)
  uint64_t http_requests = 0;
  uint64_t http_bad_requests = 0;  // unparsable or oversized requests
  uint64_t http_timeouts = 0;      // requests not completed within request_timeout
  uint64_t not_found = 0;
  uint64_t token_refused = 0;    // /ws or /stats without a valid token
  uint64_t over_capacity = 0;    // /ws refused: max_browsers reached
  uint64_t browsers_opened = 0;  // WebSocket sessions accepted
  uint64_t browsers_open = 0;    // open now
  uint64_t bad_frames = 0;       // malformed or oversized WebSocket frames from a browser
  uint64_t client_messages = 0;  // well-formed messages from browsers (ignored)
  uint64_t stalled = 0;          // browsers disconnected because a write took too long
  uint64_t idle_closed = 0;      // browsers silent (no pong) for idle_timeout
  uint64_t aborted = 0;          // sessions ended by a transport error (reset, truncated TLS)
  uint64_t frames_written = 0;
  uint64_t frames_dropped = 0;  // frames a slow browser never got (a newer one replaced it)
  uint64_t huds_written = 0;
};

class WebServer {
 public:
  // Loads the certificate, key and CA, binds and listens; null with `error` when any fails.
  // `extra_stats`: more JSON members ("\"key\":value,...") for /stats, called on the network
  // thread; may be empty.
  static std::unique_ptr<WebServer> Create(const WebServerOptions& options,
                                           std::function<std::string()> extra_stats,
                                           std::string* error);
  ~WebServer();  // closes every connection and joins the network thread
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  void Start();
  int port() const;
  // Offers the frame to every browser (both eyes to those that asked for the anaglyph).
  void BroadcastFrame(const ComposedFrame& frame);
  void BroadcastHud(std::shared_ptr<const std::string> hud_json);
  bool WantsBothEyes() const;  // a browser asked for the right eye too
  size_t browsers() const;
  WebServerStats Stats() const;
  std::string StatsJson() const;

  class Impl;

 private:
  explicit WebServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace mostar::web

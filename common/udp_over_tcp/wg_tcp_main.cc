// mostar_wg_tcp: the Internet deployment's fallback where UDP is blocked. It carries the
// WireGuard overlay's UDP datagrams over one TCP connection per host to the hub
// (docs/networking.md, "TCP fallback"); DDS still runs over UDP inside the overlay, so no DDS
// TCP transport is involved.
//   mostar_wg_tcp client --hub HOST:PORT [--listen 127.0.0.1:51821]   on a robot or operator
//       computer whose WireGuard names 127.0.0.1:51821 as the hub's endpoint
//   mostar_wg_tcp server [--listen 0.0.0.0:51821] [--wireguard 127.0.0.1:51820]   on the hub
// Datagrams that do not fit the small send queue are dropped, never queued for long: control
// never waits behind video. Counters every --stats-period-s seconds on stderr; SIGINT/SIGTERM
// end it within the poll period (200 ms). Exit status 1 on bad options or an unusable port.
#include <CLI/CLI.hpp>
#include <chrono>
#include <string>

#include "common/log/log.h"
#include "common/process/stop_signals.h"
#include "common/udp_over_tcp/tunnel_client.h"
#include "common/udp_over_tcp/tunnel_server.h"

namespace mostar::udp_over_tcp {
namespace {

constexpr int kPollMs = 200;  // bounds the reaction to SIGTERM

void LogEvents(std::vector<std::string> events) {
  for (const auto& e : events) MOSTAR_LOG(INFO) << e;
}

template <typename Tunnel, typename Report>
int Run(Tunnel& tunnel, double stats_period_s, const Report& report) {
  std::string error;
  if (!tunnel.Open(&error)) {
    MOSTAR_LOG(ERROR) << error;
    return 1;
  }
  LogEvents(tunnel.TakeEvents());
  using Clock = std::chrono::steady_clock;
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(stats_period_s));
  auto next_report = Clock::now() + period;
  while (!StopRequested()) {
    tunnel.Poll(kPollMs);
    LogEvents(tunnel.TakeEvents());
    if (Clock::now() >= next_report) {
      next_report += period;
      MOSTAR_LOG(INFO) << report(tunnel);
    }
  }
  MOSTAR_LOG(INFO) << "stopping; " << report(tunnel);
  return 0;
}

int Main(int argc, char** argv) {
  CLI::App app("mostar_wg_tcp: the WireGuard overlay's datagrams over TCP where UDP is blocked");
  app.require_subcommand(1);
  StreamLinkOptions link;
  TcpTuning tcp;
  double stats_period_s = 5;
  auto add_common = [&](CLI::App* sub) {
    sub->add_option("--max-datagram-bytes", link.max_datagram_bytes,
                    "largest datagram accepted from the stream")
        ->check(CLI::Range(64, 65535));
    sub->add_option("--queue-bytes", link.queue_bytes,
                    "send queue per connection (framed bytes); more is dropped")
        ->check(CLI::Range(2048, 16 * 1024 * 1024));
    sub->add_option("--max-unsent-bytes", link.max_unsent_bytes,
                    "bytes written to TCP but not sent yet, at most (TCP_NOTSENT_LOWAT)")
        ->check(CLI::Range(1024, 16 * 1024 * 1024));
    sub->add_option("--user-timeout-ms", tcp.user_timeout_ms,
                    "a connection whose data stays unacknowledged this long ends")
        ->check(CLI::Range(500, 600000));
    sub->add_option("--congestion", tcp.congestion, "TCP congestion control ('' = default)");
    sub->add_option("--stats-period-s", stats_period_s, "counters on stderr every so often")
        ->check(CLI::Range(0.1, 3600.0));
  };
  TunnelClientOptions client_options;
  CLI::App* client = app.add_subcommand("client", "on a robot or operator computer");
  client->add_option("--hub", client_options.hub, "HOST:PORT of the hub's tunnel")->required();
  client->add_option("--listen", client_options.listen,
                     "local UDP address that WireGuard uses as the hub's endpoint");
  client
      ->add_option("--connect-timeout-ms", client_options.connect_timeout_ms,
                   "connect and preamble within this")
      ->check(CLI::Range(100, 60000));
  client
      ->add_option("--dial-interval-ms", client_options.dial_interval_ms,
                   "a new dial this often while the path answers nothing")
      ->check(CLI::Range(50, 60000));
  client
      ->add_option("--max-backoff-ms", client_options.max_backoff_ms, "longest wait between dials")
      ->check(CLI::Range(250, 60000));
  client
      ->add_option("--held-datagrams", client_options.held_datagrams,
                   "datagrams kept while the hub is unreachable, sent first once it is back")
      ->check(CLI::Range(0, 1024));
  add_common(client);
  TunnelServerOptions server_options;
  CLI::App* server = app.add_subcommand("server", "on the hub");
  server->add_option("--listen", server_options.listen, "TCP address clients dial");
  server->add_option("--wireguard", server_options.wireguard, "the hub's WireGuard UDP port");
  server->add_option("--max-clients", server_options.max_clients, "connections at a time")
      ->check(CLI::Range(1, 4096));
  add_common(server);
  CLI11_PARSE(app, argc, argv);
  tcp.notsent_lowat_bytes = link.max_unsent_bytes;

  InstallStopSignals();
  if (client->parsed()) {
    client_options.link = link;
    client_options.tcp = tcp;
    TunnelClient tunnel(client_options);
    return Run(tunnel, stats_period_s, [](const TunnelClient& t) {
      const TunnelClientCounters c = t.counters();
      return std::string(t.connected() ? "connected" : "not connected") + ": udp in " +
             std::to_string(c.udp_in) + ", udp out " + std::to_string(c.udp_out) +
             ", dropped: queue full " + std::to_string(c.dropped_queue) + ", no link " +
             std::to_string(c.dropped_no_link) + ", no sender " +
             std::to_string(c.dropped_no_sender) + "; held and sent on reconnection " +
             std::to_string(c.held_sent) + "; dials " + std::to_string(c.dials) + ", connects " +
             std::to_string(c.connects) + ", failures " + std::to_string(c.failures) +
             ", name lookups " + std::to_string(c.lookups);
    });
  }
  server_options.link = link;
  server_options.tcp = tcp;
  TunnelServer tunnel(server_options);
  return Run(tunnel, stats_period_s, [](const TunnelServer& t) {
    const TunnelServerCounters c = t.counters();
    return std::to_string(c.clients) + " clients: to wireguard " + std::to_string(c.tcp_in) +
           ", from wireguard " + std::to_string(c.tcp_out) + ", dropped: queue full " +
           std::to_string(c.dropped_queue) + ", udp " + std::to_string(c.dropped_udp) +
           "; accepted " + std::to_string(c.accepted) + ", refused " + std::to_string(c.refused) +
           ", closed " + std::to_string(c.closed);
  });
}

}  // namespace
}  // namespace mostar::udp_over_tcp

int main(int argc, char** argv) { return mostar::udp_over_tcp::Main(argc, argv); }

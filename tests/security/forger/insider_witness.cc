// insider_witness: what the robot publishes, as a legitimate observer sees it (a Cyclone DDS
// participant with its own, honest credentials). Until --duration-s it prints one line per
// health or lease sample:
//   WITNESS t=S kind=health estop=0|1 holder=ID last_command_sequence=N rejected_stale=N
//     estop_refused=N
//   WITNESS t=S kind=lease holder=ID lease_sequence=N
// (t in wall-clock seconds; counters -1 when absent). Exit 1 when it could not join the domain.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <thread>

#include "cyclone_participant.h"

#ifndef MOSTAR_CYCLONE_AUTH_LIBRARY
#define MOSTAR_CYCLONE_AUTH_LIBRARY ""
#endif
#ifndef MOSTAR_CYCLONE_AC_LIBRARY
#define MOSTAR_CYCLONE_AC_LIBRARY ""
#endif
#ifndef MOSTAR_CYCLONE_CRYPTO_LIBRARY
#define MOSTAR_CYCLONE_CRYPTO_LIBRARY ""
#endif

namespace mostar::forger {
namespace {

long long CounterOf(const mostar_msgs_msg_dds__RobotHealth_& h, const char* device,
                    const char* name) {
  for (uint32_t i = 0; i < h.devices._length; ++i) {
    const auto& d = h.devices._buffer[i];
    if (std::strcmp(d.name, device) != 0) continue;
    for (uint32_t j = 0; j < d.counters._length; ++j) {
      if (std::strcmp(d.counters._buffer[j].name, name) == 0) {
        return static_cast<long long>(d.counters._buffer[j].value);
      }
    }
  }
  return -1;
}

dds_entity_t Reader(dds_entity_t participant, const char* name,
                    const dds_topic_descriptor_t* descriptor, bool transient_local) {
  const dds_entity_t topic = dds_create_topic(participant, descriptor, name, nullptr, nullptr);
  if (topic < 0) return topic;
  dds_qos_t* qos = EndpointQos(transient_local ? 1 : 16, transient_local);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  return reader;
}

int Run(int domain, const Credentials& credentials, const Plugins& plugins, double duration_s) {
  std::string error;
  const dds_entity_t participant =
      CreateSecureParticipant(domain, credentials, plugins, {}, &error);
  if (participant < 0) {
    std::fprintf(stderr, "insider_witness: %s\n", error.c_str());
    return 1;
  }
  const dds_entity_t health =
      Reader(participant, kHealth, &mostar_msgs_msg_dds__RobotHealth__desc, false);
  const dds_entity_t lease =
      Reader(participant, kLease, &mostar_msgs_msg_dds__ControlLease__desc, true);
  if (health < 0 || lease < 0) {
    std::fprintf(stderr, "insider_witness: readers refused: %s %s\n", dds_strretcode(health),
                 dds_strretcode(lease));
    dds_delete(participant);
    return 1;
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
  while (std::chrono::steady_clock::now() < end) {
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    int n = dds_take(health, samples, infos, 8, 8);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* h = static_cast<const mostar_msgs_msg_dds__RobotHealth_*>(samples[i]);
      std::printf(
          "WITNESS t=%.3f kind=health estop=%d holder=%s last_command_sequence=%llu "
          "rejected_stale=%lld estop_refused=%lld\n",
          WallSeconds(), h->estop_engaged ? 1 : 0, h->lease_holder[0] ? h->lease_holder : "-",
          static_cast<unsigned long long>(h->last_command_sequence),
          CounterOf(*h, "drive_safety", "rejected_stale"),
          CounterOf(*h, "drive_safety", "estop_refused"));
    }
    if (n > 0) dds_return_loan(health, samples, n);
    n = dds_take(lease, samples, infos, 8, 8);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* l = static_cast<const mostar_msgs_msg_dds__ControlLease_*>(samples[i]);
      std::printf("WITNESS t=%.3f kind=lease holder=%s lease_sequence=%llu\n", WallSeconds(),
                  l->holder_id[0] ? l->holder_id : "-",
                  static_cast<unsigned long long>(l->lease_sequence));
    }
    if (n > 0) dds_return_loan(lease, samples, n);
    std::fflush(stdout);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  dds_delete(participant);
  return 0;
}

}  // namespace
}  // namespace mostar::forger

int main(int argc, char** argv) {
  mostar::forger::Credentials c;
  mostar::forger::Plugins p;
  p.auth_path = MOSTAR_CYCLONE_AUTH_LIBRARY;
  p.access_path = MOSTAR_CYCLONE_AC_LIBRARY;
  p.crypto_path = MOSTAR_CYCLONE_CRYPTO_LIBRARY;
  int domain = 0;
  double duration_s = 60;
  CLI::App app{"insider_witness: prints the robot's health and lease as an observer sees them"};
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--identity-ca", c.identity_ca, "identity CA certificate (PEM)")->required();
  app.add_option("--cert", c.cert, "own certificate (PEM)")->required();
  app.add_option("--key", c.key, "own private key (PEM)")->required();
  app.add_option("--permissions-ca", c.permissions_ca, "permissions CA (PEM)")->required();
  app.add_option("--governance", c.governance, "signed governance (.p7s)")->required();
  app.add_option("--permissions", c.permissions, "own signed permissions (.p7s)")->required();
  app.add_option("--duration-s", duration_s, "run this long");
  app.add_option("--auth-library", p.auth_path, "Cyclone's authentication plugin");
  app.add_option("--access-library", p.access_path, "Cyclone's access control plugin");
  app.add_option("--crypto-library", p.crypto_path, "Cyclone's cryptography plugin");
  CLI11_PARSE(app, argc, argv);
  return mostar::forger::Run(domain, c, p, duration_s);
}

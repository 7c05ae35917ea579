// identity_actor: a DDS participant that talks to robot_server as an operator console would,
// under whatever sender_id it is told to claim, with whatever certificate its profile holds.
// Used by sender_identity_test to play pilots, observers and impostors.
//
// Writers are created only for what it is told to send (an observer's permissions allow no
// cmd_vel or control request writer). Every 50 ms, until --duration-s: a take request every
// 500 ms (--take), a release request every 500 ms (--release), a velocity command (--commands
// idle: enable=false, zero velocity; drive: enable=false for 10 commands, then enable=true at
// --angular rad/s), an e-stop (--estop engage|release, every 200 ms), a clock ping every 200 ms
// (--pings). Lines on standard input change the plan while it runs: "drive W" (arm, then turn at
// W rad/s) and "estop engage" / "estop release" (send that e-stop from now on).
// Prints one line at the end: "actor: commands=N requests=N estops=N pings=N".
//
// Its writers are in its own client partition, as a console's (common/identity/
// sender_partition.h: the certificate's CN, or without DDS Security the sender_id). With
// --move-to-partition-of ID they are created there, then the publisher's partition is changed
// to ID's: an insider on stock Fast DDS, whose own permissions check runs only when a writer is
// created, announcing its writers in another client's partition. The robot's access control must
// refuse them.
#include <CLI/CLI.hpp>
#include <atomic>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include "common/dds/conversions.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
#include "common/identity/sender_partition.h"
#include "common/time/time.h"
#include "mostar_msgsPubSubTypes.h"

namespace mostar {
namespace {

namespace topics = dds::topics;
using dds::Stream;

struct Plan {
  std::string commands;  // "", "idle" or "drive"
  double angular_radps = 0;
  std::string estop;  // "", "engage" or "release"
};

template <class W>
bool WaitMatched(const std::unique_ptr<W>& writer, std::chrono::seconds timeout) {
  if (!writer) return true;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (writer->matched() == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return writer->matched() > 0;
}

int Run(int argc, char** argv) {
  CLI::App app{"identity_actor: an operator console under a chosen sender_id (tests)"};
  std::string profile = "loopback";
  int domain = 0;
  std::string sender_id;
  double duration_s = 5;
  bool take = false;
  bool release = false;
  bool pings = false;
  uint64_t first_sequence = 1;
  Plan initial;
  app.add_option("--dds-profile", profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--sender-id", sender_id, "the sender_id written in every message")->required();
  app.add_option("--duration-s", duration_s, "run this long")->check(CLI::PositiveNumber);
  app.add_flag("--take", take, "ask for the lease every 500 ms");
  app.add_flag("--release", release, "release the lease every 500 ms");
  app.add_option("--commands", initial.commands, "idle | drive")
      ->check(CLI::IsMember({"idle", "drive"}));
  app.add_option("--angular", initial.angular_radps, "turn rate when driving, rad/s");
  app.add_option("--first-sequence", first_sequence, "sequence number of the first command");
  app.add_option("--estop", initial.estop, "engage | release")
      ->check(CLI::IsMember({"engage", "release"}));
  app.add_flag("--pings", pings, "send clock pings");
  bool insecure = false;
  app.add_flag("--insecure", insecure, "allow a network profile without DDS Security");
  bool stdin_plan = false;
  app.add_flag("--stdin", stdin_plan, "read plan changes from standard input");
  std::string move_to;
  app.add_option("--move-to-partition-of", move_to,
                 "once created, move the writers into this client's partition");
  CLI11_PARSE(app, argc, argv);

  dds::ParticipantOptions options;
  options.domain_id = domain;
  options.profile = profile;
  options.name = "operator";
  options.insecure = insecure;
  std::string error;
  std::unique_ptr<dds::Participant> participant;
  const bool commands = !initial.commands.empty() || stdin_plan;
  const bool estops = !initial.estop.empty() || stdin_plan;
  using CommandWriter = dds::Writer<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>;
  using RequestWriter = dds::Writer<mostar_msgs::msg::dds_::ControlRequest_PubSubType>;
  using EstopWriter = dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>;
  using PingWriter = dds::Writer<mostar_msgs::msg::dds_::ClockProbe_PubSubType>;
  std::unique_ptr<CommandWriter> command_writer;
  std::unique_ptr<RequestWriter> request_writer;
  std::unique_ptr<EstopWriter> estop_writer;
  std::unique_ptr<PingWriter> ping_writer;
  std::string own_id;
  const auto set_partition = [&](const std::string& client_id) {
    eprosima::fastdds::dds::PublisherQos qos = participant->publisher()->get_qos();
    qos.partition().clear();
    qos.partition().push_back(identity::SenderPartition(client_id).c_str());
    return participant->publisher()->set_qos(qos) == ReturnCode_t::RETCODE_OK;
  };
  // Joins as a console does: 0 matched, 1 failed for good, 2 not matched in 15 s.
  const auto join = [&]() -> int {
    command_writer.reset();
    request_writer.reset();
    estop_writer.reset();
    ping_writer.reset();
    participant.reset();
    participant = dds::Participant::Create(options, &error);
    if (!participant) {
      std::cerr << "identity_actor: " << error << "\n";
      return 1;
    }
    // The writers take the publisher's partition (no partition of their own), so that it can be
    // changed after they are created.
    own_id = participant->own_client_id().empty() ? sender_id : participant->own_client_id();
    if (!identity::IsValidClientId(own_id) ||
        (!move_to.empty() && !identity::IsValidClientId(move_to))) {
      std::cerr << "identity_actor: invalid client id\n";
      return 1;
    }
    if (!set_partition(own_id)) {
      std::cerr << "identity_actor: cannot set the publisher's partition\n";
      return 1;
    }
    if (commands) {
      command_writer =
          std::make_unique<CommandWriter>(*participant, topics::kCommand, Stream::kCommand);
    }
    if (take || release) {
      request_writer =
          std::make_unique<RequestWriter>(*participant, topics::kControlRequest, Stream::kControl);
    }
    if (estops) {
      estop_writer =
          std::make_unique<EstopWriter>(*participant, topics::kEmergencyStop, Stream::kControl);
    }
    if (pings) {
      ping_writer =
          std::make_unique<PingWriter>(*participant, topics::kClockPing, Stream::kControl);
    }
    for (const bool ok :
         {!command_writer || command_writer->ok(), !request_writer || request_writer->ok(),
          !estop_writer || estop_writer->ok(), !ping_writer || ping_writer->ok()}) {
      if (!ok) {
        std::cerr << "identity_actor: a writer could not be created (permissions?)\n";
        return 1;
      }
    }
    const auto wait = std::chrono::seconds(15);
    if (!WaitMatched(command_writer, wait) || !WaitMatched(request_writer, wait) ||
        !WaitMatched(estop_writer, wait) || !WaitMatched(ping_writer, wait)) {
      const auto count = [](const auto& writer) {
        return writer ? std::to_string(writer->matched()) : std::string("-");
      };
      std::cerr << "identity_actor: the robot's readers were not matched (readers matched: "
                   "cmd_vel "
                << count(command_writer) << ", control request " << count(request_writer)
                << ", estop " << count(estop_writer) << ", clock ping " << count(ping_writer)
                << ")\n";
      return 2;
    }
    return 0;
  };
  // With DDS Security, Fast DDS 2.9.1 can leave a remote participant discovered but never
  // authenticated when it discovers two participants at the same moment on two receive threads
  // (docs/networking.md, Known limits): an operator would reconnect, and so does this console,
  // twice at most. The new participant has a new GUID, so both sides start afresh.
  int joined = join();
  for (int rejoin = 0; joined == 2 && rejoin < 2; ++rejoin) {
    std::cerr << "identity_actor: joins again\n";
    joined = join();
  }
  if (joined != 0) return 1;
  if (!move_to.empty()) {
    if (!set_partition(move_to)) {
      std::cerr << "identity_actor: cannot move to the partition of " << move_to << "\n";
      return 1;
    }
    std::cerr << "identity_actor: writers moved to " << identity::SenderPartition(move_to) << "\n";
  }

  // Shared with the stdin reader, which may outlive this function (it is detached).
  struct State {
    std::mutex mutex;
    Plan plan;
    int drive_arming = 10;  // enable=false commands before enable=true
  };
  auto state = std::make_shared<State>();
  state->plan = initial;
  if (stdin_plan) {
    std::thread([state] {
      std::string line;
      while (std::getline(std::cin, line)) {
        std::istringstream words(line);
        std::string verb;
        words >> verb;
        std::lock_guard<std::mutex> lock(state->mutex);
        if (verb == "drive") {
          state->plan.commands = "drive";
          words >> state->plan.angular_radps;
          state->drive_arming = 10;
        } else if (verb == "estop") {
          words >> state->plan.estop;
        }
      }
    }).detach();
  }

  const Clock& clock = SystemClock::Instance();
  uint64_t sequence = first_sequence;
  int sent_commands = 0, sent_requests = 0, sent_estops = 0, sent_pings = 0;
  const auto end = std::chrono::steady_clock::now() + FromSeconds(duration_s);
  for (int tick = 0; std::chrono::steady_clock::now() < end; ++tick) {
    Plan now_plan;
    bool arming = false;
    {
      std::lock_guard<std::mutex> lock(state->mutex);
      now_plan = state->plan;
      if (now_plan.commands == "drive" && state->drive_arming > 0) {
        arming = true;
        --state->drive_arming;
      }
    }
    if (request_writer && tick % 10 == 0) {
      ControlRequest request;
      request.stamp = clock.Now();
      request.sender_id = sender_id;
      request.take = take;
      if (request_writer->Write(dds::ToIdl(request))) ++sent_requests;
    }
    if (command_writer && !now_plan.commands.empty()) {
      VelocityCommand command;
      command.stamp = clock.Now();
      command.sequence = sequence++;
      command.sender_id = sender_id;
      command.enable = now_plan.commands == "drive" && !arming;
      command.angular_radps = command.enable ? now_plan.angular_radps : 0;
      if (command_writer->Write(dds::ToIdl(command))) ++sent_commands;
    }
    if (estop_writer && !now_plan.estop.empty() && tick % 4 == 0) {
      EmergencyStop stop;
      stop.stamp = clock.Now();
      stop.sender_id = sender_id;
      stop.engage = now_plan.estop == "engage";
      if (estop_writer->Write(dds::ToIdl(stop))) ++sent_estops;
    }
    if (ping_writer && tick % 4 == 0) {
      ClockProbe ping;
      ping.sender_id = sender_id;
      ping.sequence = static_cast<uint64_t>(tick / 4 + 1);
      ping.t0 = clock.Now();
      if (ping_writer->Write(dds::ToIdl(ping))) ++sent_pings;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::cout << "actor: commands=" << sent_commands << " requests=" << sent_requests
            << " estops=" << sent_estops << " pings=" << sent_pings << std::endl;
  return 0;
}

}  // namespace
}  // namespace mostar

int main(int argc, char** argv) { return mostar::dds::EndProcess(mostar::Run(argc, argv)); }

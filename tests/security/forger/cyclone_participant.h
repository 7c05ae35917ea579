// A Cyclone DDS participant on a mostar secure domain (the DDS Security files of
// deploy/security/make_pki.sh), for the insider tools. Header only; every function returns a
// negative entity or false on failure with a message in *error.
#pragma once

#include <dds/dds.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mostar_msgs.h"

namespace mostar::forger {

// Topic and type names as robot_server uses them (common/dds/topics.h).
inline constexpr const char* kCommand = "rt/mostar/cmd_vel";
inline constexpr const char* kEstop = "rt/mostar/estop";
inline constexpr const char* kRequest = "rt/mostar/control/request";
inline constexpr const char* kLease = "rt/mostar/control/lease";
inline constexpr const char* kHealth = "rt/mostar/health";
inline constexpr const char* kPing = "rt/mostar/clock/ping";
inline constexpr const char* kPong = "rt/mostar/clock/pong";
inline constexpr const char* kSenderPartitionPrefix = "mostar.client.";

// The DDS Security files of one participant, as paths.
struct Credentials {
  std::string identity_ca;
  std::string cert;
  std::string key;
  std::string permissions_ca;
  std::string governance;
  std::string permissions;
};

// The security plugin libraries: authentication (path, init and finalize function names),
// access control and cryptography (Cyclone's builtin entry points).
struct Plugins {
  std::string auth_path;
  std::string auth_init = "init_authentication";
  std::string auth_finalize = "finalize_authentication";
  std::string access_path;
  std::string access_init = "init_access_control";
  std::string access_finalize = "finalize_access_control";
  std::string crypto_path;
};

inline std::string FileUri(const std::string& path) { return "file:" + path; }

// Creates a participant on `domain` with DDS Security and `user_data` in its USER_DATA QoS.
inline dds_entity_t CreateSecureParticipant(int domain, const Credentials& c, const Plugins& p,
                                            const std::vector<uint8_t>& user_data,
                                            std::string* error) {
  dds_qos_t* qos = dds_create_qos();
  const std::pair<const char*, std::string> props[] = {
      {"dds.sec.auth.library.path", p.auth_path},
      {"dds.sec.auth.library.init", p.auth_init},
      {"dds.sec.auth.library.finalize", p.auth_finalize},
      {"dds.sec.auth.identity_ca", FileUri(c.identity_ca)},
      {"dds.sec.auth.identity_certificate", FileUri(c.cert)},
      {"dds.sec.auth.private_key", FileUri(c.key)},
      {"dds.sec.access.library.path", p.access_path},
      {"dds.sec.access.library.init", p.access_init},
      {"dds.sec.access.library.finalize", p.access_finalize},
      {"dds.sec.access.permissions_ca", FileUri(c.permissions_ca)},
      {"dds.sec.access.governance", FileUri(c.governance)},
      {"dds.sec.access.permissions", FileUri(c.permissions)},
      {"dds.sec.crypto.library.path", p.crypto_path},
      {"dds.sec.crypto.library.init", "init_crypto"},
      {"dds.sec.crypto.library.finalize", "finalize_crypto"},
  };
  for (const auto& [name, value] : props) dds_qset_prop(qos, name, value.c_str());
  if (!user_data.empty()) dds_qset_userdata(qos, user_data.data(), user_data.size());
  const dds_entity_t participant =
      dds_create_participant(static_cast<dds_domainid_t>(domain), qos, nullptr);
  dds_delete_qos(qos);
  if (participant < 0) {
    *error = std::string("dds_create_participant: ") + dds_strretcode(participant) +
             " (wrong credentials, or the security plugins cannot be loaded)";
  }
  return participant;
}

// Reliable keep-last `depth` QoS; `partition` empty: the default partition.
inline dds_qos_t* EndpointQos(int depth, bool transient_local) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  dds_qset_durability(qos,
                      transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  return qos;
}

// Seconds since the epoch, wall clock (the robot's stamps use the same clock on one machine).
inline double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
inline int64_t WallNanos() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
inline builtin_interfaces_msg_dds__Time_ Stamp(int64_t ns) {
  builtin_interfaces_msg_dds__Time_ t;
  t.sec = static_cast<int32_t>(ns / 1'000'000'000);
  t.nanosec = static_cast<uint32_t>(ns % 1'000'000'000);
  return t;
}
inline int64_t Nanos(const builtin_interfaces_msg_dds__Time_& t) {
  return int64_t{t.sec} * 1'000'000'000 + t.nanosec;
}

// Copies `s` into a bounded IDL string field.
template <size_t N>
void SetString(char (&field)[N], const std::string& s) {
  std::memset(field, 0, N);
  std::memcpy(field, s.data(), std::min(s.size(), N - 1));
}

}  // namespace mostar::forger

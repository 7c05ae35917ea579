// The DDS partition that proves who wrote a command, an e-stop, a control request or a clock
// ping.
//
// Each client writes those four topics in exactly one partition, "mostar.client.<its client
// id>". Under DDS Security the permissions signed for a certificate allow it to publish them in
// its own partition only (deploy/security/make_pki.sh), and Fast DDS checks a remote writer's
// partitions against the permissions of the certificate that authenticated in the handshake,
// not against anything the participant announces (its GUID, its USER_DATA). So a sample that
// reaches the robot's reader in partition "mostar.client.alice" was written under the
// certificate of alice: the robot keeps one reader per client of its role table and takes the
// client id from the reader, never from the writer's GUID (docs/security.md, Identities).
// Without DDS Security the partition is only a claim, like sender_id.
//
// Client ids never hold the pattern characters of partition matching (* ? [ ]: client_id.h),
// so a client's partition matches no other client's. Pure.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace mostar::identity {

inline constexpr std::string_view kSenderPartitionPrefix = "mostar.client.";
// Matches every client's partition: the robot's reader of clock pings from clients outside its
// role table, and the relay's reader of observers' e-stops.
inline constexpr const char* kAnySenderPartition = "mostar.client.*";

// "mostar.client.<client_id>"; `client_id` must be valid (IsValidClientId, checked).
std::string SenderPartition(std::string_view client_id);

// The client id whose partition `partition` is; nullopt for anything else (another prefix, an
// invalid id, a pattern).
std::optional<std::string> ClientIdOfSenderPartition(std::string_view partition);

}  // namespace mostar::identity

#include "common/identity/sender_partition.h"

#include "common/check/check.h"
#include "common/identity/client_id.h"

namespace mostar::identity {

std::string SenderPartition(std::string_view client_id) {
  std::string why;
  MOSTAR_CHECK(IsValidClientId(client_id, &why)) << why;
  return std::string(kSenderPartitionPrefix) + std::string(client_id);
}

std::optional<std::string> ClientIdOfSenderPartition(std::string_view partition) {
  if (partition.substr(0, kSenderPartitionPrefix.size()) != kSenderPartitionPrefix) {
    return std::nullopt;
  }
  const std::string_view id = partition.substr(kSenderPartitionPrefix.size());
  if (!IsValidClientId(id)) return std::nullopt;
  return std::string(id);
}

}  // namespace mostar::identity

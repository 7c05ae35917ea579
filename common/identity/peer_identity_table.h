// Which client id each remote DDS participant announces, for logs and diagnostics only.
//
// The DDS glue (common/dds/participant.cc) feeds two facts per participant, by GUID prefix:
// `Bind` when the certificate it announced was verified (issued by the identity CA, subject
// hash matching its GUID prefix: guid_binding.h), `MarkAuthenticated` when DDS Security
// authenticated it. Both together still do not prove the id: Fast DDS 2.9's PKI-DH does not
// check that the certificate of the handshake is the announced one, so an insider with any
// certificate of the CA can announce another client's GUID and certificate and authenticate.
// No authorization may rest on this table: privileges follow the DDS partition a writer is
// matched in, which only the signed permissions of the handshake's certificate allow
// (common/identity/sender_partition.h, docs/security.md, Identities).
//
// A binding is never replaced by a different id (a later announcement cannot rebind a prefix),
// only `Forget` (the participant left) removes it.
//
// Bounded: at most `max_peers` participants, at most `max_per_client` of them per client id.
// A new participant over either limit evicts the oldest entry that is not complete (bound and
// authenticated; for the per-client limit, of that id), or is refused and counted: however
// many participants announce an id, a complete entry of it is never evicted. Thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "common/identity/guid_binding.h"

namespace mostar::identity {

struct PeerIdentityStats {
  uint64_t bound = 0;               // Bind calls that set a binding
  uint64_t rebind_refused = 0;      // Bind with another id for an already bound prefix
  uint64_t evicted = 0;             // entries dropped to make room
  uint64_t refused_full = 0;        // new participants refused: every slot holds a complete entry
  uint64_t refused_per_client = 0;  // Bind refused: the id's share holds only complete entries
  size_t peers = 0;                 // entries now
};

class PeerIdentityTable {
 public:
  // Both limits >= 1 (checked).
  explicit PeerIdentityTable(size_t max_peers = 256, size_t max_per_client = 4);

  // The participant `prefix` holds a verified certificate of `client_id`. False (counted) when
  // the prefix is bound to another id already, or when there is no room.
  bool Bind(const GuidPrefix& prefix, const std::string& client_id);
  // DDS Security authenticated the participant. False when there is no room.
  bool MarkAuthenticated(const GuidPrefix& prefix);
  // The participant left the domain.
  void Forget(const GuidPrefix& prefix);

  // The client id whose verified certificate `prefix` announced, when it also authenticated
  // (or whatever its state, with `authenticated_only` false); nullopt for any other participant.
  // A claim, not a proof (see above).
  std::optional<std::string> AnnouncedClientId(const GuidPrefix& prefix,
                                               bool authenticated_only = true) const;

  PeerIdentityStats stats() const;

 private:
  struct Entry {
    std::string client_id;  // empty until bound
    bool authenticated = false;
    uint64_t order = 0;  // insertion order (eviction picks the smallest)
  };
  // Finds or makes the entry of `prefix`; null when there is no room.
  Entry* EntryLocked(const GuidPrefix& prefix);
  bool EvictOldestLocked(bool incomplete_only, const std::string& client_id);

  const size_t max_peers_;
  const size_t max_per_client_;
  mutable std::mutex mutex_;
  std::map<GuidPrefix, Entry> entries_;
  uint64_t next_order_ = 0;
  PeerIdentityStats stats_;
};

}  // namespace mostar::identity

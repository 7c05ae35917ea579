#include "common/identity/peer_identity_table.h"

#include "common/check/check.h"

namespace mostar::identity {

PeerIdentityTable::PeerIdentityTable(size_t max_peers, size_t max_per_client)
    : max_peers_(max_peers), max_per_client_(max_per_client) {
  MOSTAR_CHECK(max_peers_ >= 1 && max_per_client_ >= 1) << "limits must be at least 1";
}

bool PeerIdentityTable::EvictOldestLocked(bool incomplete_only, const std::string& client_id) {
  auto oldest = entries_.end();
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    const Entry& e = it->second;
    if (incomplete_only && !e.client_id.empty() && e.authenticated) continue;
    if (!client_id.empty() && e.client_id != client_id) continue;
    if (oldest == entries_.end() || e.order < oldest->second.order) oldest = it;
  }
  if (oldest == entries_.end()) return false;
  entries_.erase(oldest);
  ++stats_.evicted;
  return true;
}

PeerIdentityTable::Entry* PeerIdentityTable::EntryLocked(const GuidPrefix& prefix) {
  auto it = entries_.find(prefix);
  if (it != entries_.end()) return &it->second;
  if (entries_.size() >= max_peers_ && !EvictOldestLocked(true, "")) {
    ++stats_.refused_full;
    return nullptr;
  }
  Entry& entry = entries_[prefix];
  entry.order = next_order_++;
  return &entry;
}

bool PeerIdentityTable::Bind(const GuidPrefix& prefix, const std::string& client_id) {
  MOSTAR_CHECK(!client_id.empty()) << "binding an empty client id";
  std::lock_guard<std::mutex> lock(mutex_);
  auto existing = entries_.find(prefix);
  if (existing != entries_.end() && !existing->second.client_id.empty()) {
    if (existing->second.client_id == client_id) return true;
    ++stats_.rebind_refused;
    return false;
  }
  size_t same_client = 0;
  for (const auto& [p, e] : entries_) same_client += e.client_id == client_id ? 1 : 0;
  // Over its share, only an incomplete entry of the id makes room: a complete one stays
  // whoever else announces the id.
  if (same_client >= max_per_client_ && !EvictOldestLocked(true, client_id)) {
    ++stats_.refused_per_client;
    return false;
  }
  Entry* entry = EntryLocked(prefix);
  if (entry == nullptr) return false;
  entry->client_id = client_id;
  ++stats_.bound;
  return true;
}

bool PeerIdentityTable::MarkAuthenticated(const GuidPrefix& prefix) {
  std::lock_guard<std::mutex> lock(mutex_);
  Entry* entry = EntryLocked(prefix);
  if (entry == nullptr) return false;
  entry->authenticated = true;
  return true;
}

void PeerIdentityTable::Forget(const GuidPrefix& prefix) {
  std::lock_guard<std::mutex> lock(mutex_);
  entries_.erase(prefix);
}

std::optional<std::string> PeerIdentityTable::AnnouncedClientId(const GuidPrefix& prefix,
                                                                bool authenticated_only) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = entries_.find(prefix);
  if (it == entries_.end() || it->second.client_id.empty() ||
      (authenticated_only && !it->second.authenticated)) {
    return std::nullopt;
  }
  return it->second.client_id;
}

PeerIdentityStats PeerIdentityTable::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PeerIdentityStats out = stats_;
  out.peers = entries_.size();
  return out;
}

}  // namespace mostar::identity

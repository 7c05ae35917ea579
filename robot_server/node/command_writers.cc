#include "robot_server/node/command_writers.h"

#include "common/check/check.h"

namespace mostar::server {

CommandWriterTracker::CommandWriterTracker(size_t max_writers) : max_writers_(max_writers) {
  MOSTAR_CHECK(max_writers_ >= 1) << "max_writers must be at least 1";
}

void CommandWriterTracker::NoteCommand(const dds::WriterId& writer, const std::string& client_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = writers_.find(writer);
  if (it == writers_.end() && writers_.size() >= max_writers_) {
    auto oldest = writers_.begin();
    for (auto w = writers_.begin(); w != writers_.end(); ++w) {
      if (w->second.last_heard < oldest->second.last_heard) oldest = w;
    }
    writers_.erase(oldest);
  }
  Entry& entry = writers_[writer];
  entry.client_id = client_id;
  entry.last_heard = ++notes_;
}

std::optional<std::string> CommandWriterTracker::WriterLost(const dds::WriterId& writer) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = writers_.find(writer);
  if (it == writers_.end()) return std::nullopt;
  const std::string client_id = it->second.client_id;
  writers_.erase(it);
  for (const auto& [w, entry] : writers_) {
    if (entry.client_id == client_id) return std::nullopt;
  }
  return client_id;
}

size_t CommandWriterTracker::writers() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return writers_.size();
}

}  // namespace mostar::server

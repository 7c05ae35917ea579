// Which client each live command writer speaks for, so that the DDS liveliness loss of a writer
// (LIVELINESS_CHANGED on cmd_vel: silent for the liveliness lease, or gone) names the client
// that lost its command stream. A client counts as lost when its last live writer is lost.
//
// A writer speaks for the client of the last admitted command it wrote (RobotNode notes only
// commands whose sender it verified, or, without DDS Security, took as written). At most
// `max_writers` writers are tracked; a new one replaces the writer heard from least recently.
// Thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "common/dds/writer_id.h"

namespace mostar::server {

class CommandWriterTracker {
 public:
  // `max_writers` >= 1 (checked).
  explicit CommandWriterTracker(size_t max_writers = 64);

  // An admitted command from `client_id`, written by `writer`.
  void NoteCommand(const dds::WriterId& writer, const std::string& client_id);
  // `writer` stopped being alive. Returns its client when that client has no other live
  // writer left; nullopt for an unknown writer or a client still writing through another.
  std::optional<std::string> WriterLost(const dds::WriterId& writer);

  size_t writers() const;

 private:
  struct Entry {
    std::string client_id;
    uint64_t last_heard = 0;
  };
  const size_t max_writers_;
  mutable std::mutex mutex_;
  std::map<dds::WriterId, Entry> writers_;
  uint64_t notes_ = 0;
};

}  // namespace mostar::server

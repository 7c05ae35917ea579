// What one browser is sent next: at most one message being written and, per kind, the newest
// one waiting. A new frame replaces a waiting frame (counted as dropped), so a slow browser gets
// fewer frames and never holds more than one frame and one HUD in memory; the DDS side and the
// other browsers never wait for it. Pure and single-threaded: the session's network thread
// calls it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace mostar::web {

enum class MessageKind { kFrame, kHud };

struct OutMessage {
  MessageKind kind = MessageKind::kFrame;
  std::shared_ptr<const std::string> bytes;  // shared by every browser; never null
};

struct OutboxCounters {
  uint64_t offered = 0;         // messages offered
  uint64_t written = 0;         // messages handed out for writing
  uint64_t frames_dropped = 0;  // frames replaced while waiting
  uint64_t huds_dropped = 0;    // HUD messages replaced while waiting
};

class ClientOutbox {
 public:
  // `message` when nothing is being written: the caller writes it now and calls Written() once
  // the write completed. Otherwise nullopt: it waits, replacing a waiting one of its kind.
  std::optional<OutMessage> Offer(OutMessage message);
  // The write completed: the next message to write (the waiting HUD first, then the frame), or
  // nullopt when none waits (the outbox is idle again).
  std::optional<OutMessage> Written();
  bool writing() const { return writing_; }
  const OutboxCounters& counters() const { return counters_; }

 private:
  bool writing_ = false;
  std::optional<OutMessage> frame_;
  std::optional<OutMessage> hud_;
  OutboxCounters counters_;
};

}  // namespace mostar::web

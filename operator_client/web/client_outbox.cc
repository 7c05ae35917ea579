#include "operator_client/web/client_outbox.h"

#include <utility>

namespace mostar::web {

std::optional<OutMessage> ClientOutbox::Offer(OutMessage message) {
  ++counters_.offered;
  if (!writing_) {
    writing_ = true;
    ++counters_.written;
    return message;
  }
  const bool frame = message.kind == MessageKind::kFrame;
  std::optional<OutMessage>& waiting = frame ? frame_ : hud_;
  if (waiting) ++(frame ? counters_.frames_dropped : counters_.huds_dropped);
  waiting = std::move(message);
  return std::nullopt;
}

std::optional<OutMessage> ClientOutbox::Written() {
  std::optional<OutMessage> next;
  if (hud_) {
    next.swap(hud_);
  } else if (frame_) {
    next.swap(frame_);
  }
  writing_ = next.has_value();
  if (writing_) ++counters_.written;
  return next;
}

}  // namespace mostar::web

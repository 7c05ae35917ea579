#include "common/udp_over_tcp/frame_queue.h"

#include <algorithm>

#include "common/udp_over_tcp/frame_codec.h"

namespace mostar::udp_over_tcp {

size_t FrameQueue::Push(const uint8_t* datagram, size_t size) {
  const size_t framed = kLengthBytes + size;
  if (size == 0 || size > kMaxDatagramBytes || framed > capacity_bytes_) {
    ++dropped_;
    return 1;
  }
  size_t dropped = 0;
  // Make room from the oldest frame that has not begun: a begun one must be finished, or the
  // stream would lose its framing.
  const size_t first_droppable = front_written_ > 0 ? 1 : 0;
  while (bytes_ + framed > capacity_bytes_ && frames_.size() > first_droppable) {
    auto victim = frames_.begin() + static_cast<std::ptrdiff_t>(first_droppable);
    bytes_ -= victim->size();
    frames_.erase(victim);
    ++dropped;
  }
  if (bytes_ + framed > capacity_bytes_) {  // only the begun frame is left and it is too big
    ++dropped;
    dropped_ += dropped;
    return dropped;
  }
  std::vector<uint8_t> frame;
  frame.reserve(framed);
  AppendFrame(datagram, size, &frame);
  bytes_ += frame.size();
  frames_.push_back(std::move(frame));
  dropped_ += dropped;
  return dropped;
}

const uint8_t* FrameQueue::front_data() const {
  return frames_.empty() ? nullptr : frames_.front().data() + front_written_;
}

size_t FrameQueue::front_size() const {
  return frames_.empty() ? 0 : frames_.front().size() - front_written_;
}

void FrameQueue::Consume(size_t bytes) {
  while (bytes > 0 && !frames_.empty()) {
    const size_t take = std::min(bytes, front_size());
    front_written_ += take;
    bytes_ -= take;
    bytes -= take;
    if (front_written_ == frames_.front().size()) {
      frames_.pop_front();
      front_written_ = 0;
    }
  }
}

void FrameQueue::Clear() {
  frames_.clear();
  front_written_ = 0;
  bytes_ = 0;
}

}  // namespace mostar::udp_over_tcp

#include "operator_client/web/eye_pairer.h"

#include <utility>

namespace mostar::web {

std::optional<CompressedStereoPair> EyePairer::Push(Eye eye, CompressedImage image) {
  ++stats_.images;
  const int self = eye == Eye::kLeft ? 0 : 1;
  std::deque<CompressedImage>& others = pending_[1 - self];
  for (auto it = others.begin(); it != others.end(); ++it) {
    if (it->stamp != image.stamp) continue;
    CompressedImage partner = std::move(*it);
    others.erase(it);
    if (last_emitted_ && image.stamp <= *last_emitted_) {
      ++stats_.late;
      return std::nullopt;
    }
    last_emitted_ = image.stamp;
    CompressedStereoPair pair;
    pair.sequence = ++stats_.pairs;
    pair.left = self == 0 ? std::move(image) : std::move(partner);
    pair.right = self == 0 ? std::move(partner) : std::move(image);
    return pair;
  }
  std::deque<CompressedImage>& mine = pending_[self];
  mine.push_back(std::move(image));
  while (mine.size() > kMaxPending) {
    mine.pop_front();
    ++stats_.unpaired;
  }
  return std::nullopt;
}

}  // namespace mostar::web

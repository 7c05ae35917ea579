#include "operator_client/calibration/fit_worker.h"

#include <utility>

#include "common/check/check.h"

namespace mostar::calibration {

FitWorker::FitWorker(const FitOptions& options) : options_(options) {
  MOSTAR_CHECK(options_.IsValid(nullptr));
  thread_ = std::thread(&FitWorker::Run, this);
}

FitWorker::~FitWorker() {
  pending_.Close();  // discards a pending request, wakes the worker
  thread_.join();
}

void FitWorker::Submit(FitInput input) { pending_.Put(std::move(input)); }

std::shared_ptr<const FitResult> FitWorker::LatestResult() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

uint64_t FitWorker::completed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return completed_;
}

bool FitWorker::WaitForCompleted(uint64_t count, Duration timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return done_.wait_for(lock, timeout, [&] { return completed_ >= count; });
}

void FitWorker::Run() {
  while (!pending_.closed()) {
    std::optional<FitInput> taken = pending_.Take(std::chrono::seconds(1));
    if (!taken) continue;
    auto result = std::make_shared<const FitResult>(FitCalibration(*taken, options_));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      latest_ = std::move(result);
      ++completed_;
    }
    done_.notify_all();
  }
}

}  // namespace mostar::calibration

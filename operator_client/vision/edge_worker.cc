#include "operator_client/vision/edge_worker.h"

#include <utility>

#include "common/check/check.h"
#include "common/log/log.h"
#include "common/sync/thread_priority.h"

namespace mostar::vision {

EdgeWorker::EdgeWorker(const VisionOptions& options, const Clock* clock)
    : custom_process_(false), clock_(clock), pipeline_(std::make_shared<VisionPipeline>(options)) {
  thread_ = std::thread(&EdgeWorker::Run, this);
}

EdgeWorker::EdgeWorker(ProcessFunction process, const Clock* clock)
    : process_(std::move(process)), custom_process_(true), clock_(clock) {
  MOSTAR_CHECK(process_);
  thread_ = std::thread(&EdgeWorker::Run, this);
}

EdgeWorker::~EdgeWorker() {
  pending_.Close();  // discards a pending input, wakes the worker
  thread_.join();
}

void EdgeWorker::Submit(VisionInput input) { pending_.Put(std::move(input)); }

bool EdgeWorker::SetOptions(const VisionOptions& options, std::string* error) {
  if (custom_process_) {
    if (error != nullptr) *error = "this worker runs a custom process function";
    return false;
  }
  if (!options.IsValid(error)) return false;
  auto pipeline = std::make_shared<VisionPipeline>(options);
  std::lock_guard<std::mutex> lock(mutex_);
  pipeline_ = std::move(pipeline);
  return true;
}

VisionOptions EdgeWorker::options() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pipeline_ != nullptr ? pipeline_->options() : VisionOptions{};
}

void EdgeWorker::SetWakeSignal(WakeSignal* signal) {
  std::lock_guard<std::mutex> lock(mutex_);
  wake_ = signal;
}

std::shared_ptr<const VisionResult> EdgeWorker::LatestResult() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

bool EdgeWorker::WaitForProcessed(uint64_t count, Duration timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return result_ready_.wait_for(lock, timeout, [&] { return stats_.processed >= count; });
}

EdgeWorker::Stats EdgeWorker::stats() const {
  const LatestValueSlot<VisionInput>::Counters slot = pending_.counters();
  std::lock_guard<std::mutex> lock(mutex_);
  Stats stats = stats_;
  stats.submitted = slot.puts;
  stats.replaced = slot.drops;
  return stats;
}

void EdgeWorker::Run() {
  // Edge processing is background work: the decoding and drawing of the pair on screen come
  // first (the overlay waits for a result at most vision_result_wait_ms anyway).
  LowerCurrentThreadPriority();
  while (!pending_.closed()) {
    std::optional<VisionInput> taken = pending_.Take(std::chrono::seconds(1));
    if (!taken) continue;
    const VisionInput& input = *taken;
    std::shared_ptr<VisionPipeline> pipeline;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pipeline = pipeline_;
    }
    auto result = std::make_shared<VisionResult>();
    if (custom_process_) {
      process_(input, result.get());
    } else {
      pipeline->Process(input, result.get());
    }
    if (!result->ok) {
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "edge processing of frame pair " << input.sequence << " failed: " << result->error;
    }
    WakeSignal* wake = nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.processed;
      if (!result->ok) ++stats_.failed;
      stats_.last_processing_time = result->processing_time;
      result->published = clock_->SteadyNow();
      latest_ = std::move(result);
      wake = wake_;
    }
    result_ready_.notify_all();
    if (wake != nullptr) wake->Notify();
  }
}

}  // namespace mostar::vision

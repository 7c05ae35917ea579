#include "operator_client/vision/edge_worker.h"

#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>

namespace mostar::vision {
namespace {

constexpr Duration kTimeout = std::chrono::seconds(10);

VisionInput InputWithSequence(uint64_t sequence) {
  VisionInput input;
  input.sequence = sequence;
  input.stamp = FromUnixNanos(static_cast<int64_t>(sequence) * 1000);
  return input;
}

// A process function that blocks until released, to hold the worker busy.
class Gate {
 public:
  void Process(const VisionInput& input, VisionResult* out) {
    std::unique_lock<std::mutex> lock(mutex_);
    ++entered_;
    changed_.notify_all();
    changed_.wait(lock, [&] { return open_; });
    out->ok = true;
    out->stamp = input.stamp;
    out->sequence = input.sequence;
  }
  void WaitEntered(int count) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return entered_ >= count; });
  }
  void Open() {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int entered_ = 0;
  bool open_ = false;
};

TEST(EdgeWorkerTest, NewInputReplacesAnUnprocessedOneAndIsCounted) {
  Gate gate;
  EdgeWorker worker([&](const VisionInput& in, VisionResult* out) { gate.Process(in, out); });
  worker.Submit(InputWithSequence(1));
  gate.WaitEntered(1);  // the worker is busy with 1
  worker.Submit(InputWithSequence(2));
  worker.Submit(InputWithSequence(3));  // replaces 2
  worker.Submit(InputWithSequence(4));  // replaces 3
  EXPECT_EQ(worker.stats().replaced, 2u);
  gate.Open();
  ASSERT_TRUE(worker.WaitForProcessed(2, kTimeout));
  const auto latest = worker.LatestResult();
  ASSERT_NE(latest, nullptr);
  EXPECT_EQ(latest->sequence, 4u);
  EXPECT_EQ(latest->stamp, FromUnixNanos(4000));
  const EdgeWorker::Stats stats = worker.stats();
  EXPECT_EQ(stats.submitted, 4u);
  EXPECT_EQ(stats.processed, 2u);
  EXPECT_EQ(stats.replaced, 2u);
}

TEST(EdgeWorkerTest, NoResultBeforeTheFirstInput) {
  EdgeWorker worker(VisionOptions{});
  EXPECT_EQ(worker.LatestResult(), nullptr);
  EXPECT_FALSE(worker.WaitForProcessed(1, std::chrono::milliseconds(1)));
}

TEST(EdgeWorkerTest, BadInputIsReportedInTheResultAndCounted) {
  EdgeWorker worker(VisionOptions{});
  worker.Submit(InputWithSequence(9));  // no images, no cameras
  ASSERT_TRUE(worker.WaitForProcessed(1, kTimeout));
  const auto latest = worker.LatestResult();
  ASSERT_NE(latest, nullptr);
  EXPECT_FALSE(latest->ok);
  EXPECT_FALSE(latest->error.empty());
  EXPECT_EQ(latest->sequence, 9u);
  EXPECT_EQ(worker.stats().failed, 1u);
}

TEST(EdgeWorkerTest, RefusesInvalidOptionsAndKeepsTheCurrentOnes) {
  EdgeWorker worker(VisionOptions{});
  VisionOptions bad;
  bad.edges.low_threshold = 250;
  std::string error;
  EXPECT_FALSE(worker.SetOptions(bad, &error));
  EXPECT_NE(error.find("edges"), std::string::npos) << error;
  EXPECT_EQ(worker.options().edges.low_threshold, VisionOptions{}.edges.low_threshold);
  VisionOptions good;
  good.edges.low_threshold = 20;
  EXPECT_TRUE(worker.SetOptions(good, &error)) << error;
  EXPECT_EQ(worker.options().edges.low_threshold, 20);
}

}  // namespace
}  // namespace mostar::vision

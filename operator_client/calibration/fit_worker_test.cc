#include "operator_client/calibration/fit_worker.h"

#include <gtest/gtest.h>

namespace mostar::calibration {
namespace {

TEST(FitWorkerTest, PublishesOneResultPerTakenRequest) {
  FitWorker worker{FitOptions{}};
  EXPECT_EQ(worker.LatestResult(), nullptr);
  FitInput input;  // no points: refused at once with a reason
  worker.Submit(input);
  ASSERT_TRUE(worker.WaitForCompleted(1, std::chrono::seconds(30)));
  const std::shared_ptr<const FitResult> result = worker.LatestResult();
  ASSERT_NE(result, nullptr);
  EXPECT_FALSE(result->ok);
  EXPECT_NE(result->reason.find("too few"), std::string::npos) << result->reason;
  EXPECT_EQ(worker.completed(), 1u);
}

TEST(FitWorkerTest, StopsWithARequestPending) {
  // The destructor must return with requests still queued (they are discarded).
  FitWorker worker{FitOptions{}};
  for (int i = 0; i < 5; ++i) worker.Submit(FitInput{});
}

}  // namespace
}  // namespace mostar::calibration

// One extra thread that runs one job at a time for its owner, to split a fixed piece of work in
// two (the two eyes of a stereo pair decoded at the same time): Run(job) hands the job over and
// returns at once, Wait() returns when it has finished.
//
// Owner thread only: Run() and Wait() are called from one thread, in turn (Run, Wait, Run, ...).
// The destructor waits for a running job, then stops the thread.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace mostar {

class HelperThread {
 public:
  HelperThread() : thread_([this] { Loop(); }) {}
  ~HelperThread() {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      done_cv_.wait(lock, [this] { return !busy_; });
      stop_ = true;
    }
    job_cv_.notify_one();
    thread_.join();
  }
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;

  void Run(std::function<void()> job) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = std::move(job);
      busy_ = true;
    }
    job_cv_.notify_one();
  }

  void Wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    done_cv_.wait(lock, [this] { return !busy_; });
  }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
      job_cv_.wait(lock, [this] { return stop_ || busy_; });
      if (!busy_) return;  // stop_ with nothing to run
      std::function<void()> job = std::move(job_);
      lock.unlock();
      job();
      lock.lock();
      busy_ = false;
      done_cv_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable job_cv_;
  std::condition_variable done_cv_;
  std::function<void()> job_;  // handed over by Run()
  bool busy_ = false;          // from Run() until the job has finished
  bool stop_ = false;
  std::thread thread_;  // last: starts after the rest exists
};

}  // namespace mostar

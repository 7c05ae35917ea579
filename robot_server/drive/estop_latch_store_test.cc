#include "robot_server/drive/estop_latch_store.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <memory>

#include "common/testing/subprocess.h"

namespace mostar::drive {
namespace {

using testing::ReadFile;

void WriteRaw(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

bool Exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

uint64_t CounterOf(const DeviceHealth& health, const std::string& name) {
  for (const auto& [counter, value] : health.counters) {
    if (counter == name) return value;
  }
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

class EstopLatchStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir("mostar_estop_");
    ASSERT_FALSE(dir_.empty());
  }
  // A new process starting on the same directory.
  EstopLatchDecision Restart() {
    store_ = std::make_unique<EstopLatchStore>(dir_);
    return store_->Start();
  }
  EstopLatchFile OnDisk() {
    EstopLatchFile file;
    std::string error;
    EXPECT_TRUE(ParseEstopLatchFile(ReadFile(store_->path()), &file, &error)) << error;
    return file;
  }

  std::string dir_;
  std::unique_ptr<EstopLatchStore> store_;
};

TEST_F(EstopLatchStoreTest, FirstStartIsUnlatchedAndRecordsARunningProcess) {
  const EstopLatchDecision decision = Restart();
  EXPECT_FALSE(decision.latched) << decision.reason;
  EXPECT_EQ(store_->path(), dir_ + "/estop_latch");
  const EstopLatchFile file = OnDisk();
  EXPECT_FALSE(file.clean_stop);
  EXPECT_FALSE(file.engaged);
  EXPECT_FALSE(Exists(store_->path() + ".tmp"));
  const DeviceHealth health = store_->Health();
  EXPECT_EQ(health.name, "estop_latch");
  EXPECT_EQ(health.state, DeviceState::kOk);
  EXPECT_NE(health.message.find("started unlatched"), std::string::npos) << health.message;
}

TEST_F(EstopLatchStoreTest, CleanStopWithTheLatchReleasedRestartsUnlatched) {
  Restart();
  std::string error;
  ASSERT_TRUE(store_->Record(true, "alice", &error)) << error;
  ASSERT_TRUE(store_->Record(false, "bob", &error)) << error;
  ASSERT_TRUE(store_->RecordCleanStop(false, "", &error)) << error;
  EXPECT_TRUE(OnDisk().clean_stop);
  const EstopLatchDecision decision = Restart();
  EXPECT_FALSE(decision.latched) << decision.reason;
  EXPECT_FALSE(OnDisk().clean_stop) << "the new run is recorded as running";
}

TEST_F(EstopLatchStoreTest, AnUncleanStopRestartsLatched) {
  Restart();  // ... and the process is killed: no RecordCleanStop
  const EstopLatchDecision decision = Restart();
  EXPECT_TRUE(decision.latched);
  EXPECT_EQ(decision.engaged_by, "");
  EXPECT_NE(decision.reason.find("did not stop cleanly"), std::string::npos) << decision.reason;
  EXPECT_TRUE(OnDisk().engaged) << "a second crash keeps the latch";
  const DeviceHealth health = store_->Health();
  EXPECT_EQ(health.state, DeviceState::kWarn);
  EXPECT_NE(health.message.find("started latched: the previous run did not stop cleanly"),
            std::string::npos)
      << health.message;
  // Released by an operator: recorded, then a clean stop restarts unlatched.
  std::string error;
  ASSERT_TRUE(store_->Record(false, "", &error)) << error;
  EXPECT_EQ(store_->Health().state, DeviceState::kOk);
  EXPECT_NE(store_->Health().message.find("released since"), std::string::npos);
  ASSERT_TRUE(store_->RecordCleanStop(false, "", &error)) << error;
  EXPECT_FALSE(Restart().latched);
}

TEST_F(EstopLatchStoreTest, AnEngagedLatchSurvivesEvenACleanStop) {
  Restart();
  std::string error;
  ASSERT_TRUE(store_->Record(true, "alice", &error)) << error;
  ASSERT_TRUE(store_->RecordCleanStop(true, "alice", &error)) << error;
  EstopLatchDecision decision = Restart();
  EXPECT_TRUE(decision.latched);
  EXPECT_EQ(decision.engaged_by, "alice");
  EXPECT_NE(decision.reason.find("engaged before the restart by alice"), std::string::npos)
      << decision.reason;
  // Engaged and then killed.
  ASSERT_TRUE(store_->Record(true, "carol", &error)) << error;
  decision = Restart();
  EXPECT_TRUE(decision.latched);
  EXPECT_EQ(decision.engaged_by, "carol");
}

TEST_F(EstopLatchStoreTest, CorruptFilesLatchAndAreReportedNeverACrash) {
  const std::string valid = FormatEstopLatchFile({true, false, ""});
  const std::string cases[] = {
      "",
      "garbage",
      std::string("\0\x01\x02\xff", 4),
      valid.substr(0, valid.size() / 2),  // truncated
      "mostar-estop-latch 2\nclean_stop 1\nengaged 0\nengaged_by -\n",
      "mostar-estop-latch 1\nclean_stop 1\nengaged 2\nengaged_by -\n",
      "mostar-estop-latch 1\nclean_stop 1\nclean_stop 1\nengaged 0\nengaged_by -\n",
      "mostar-estop-latch 1\nclean_stop 1\nengaged 0\nengaged_by a b\n",
      valid + "extra 1\n",
      valid + std::string(EstopLatchStore::kMaxFileBytes, '#'),
  };
  for (const std::string& text : cases) {
    WriteRaw(dir_ + "/estop_latch", text);
    const EstopLatchDecision decision = Restart();
    EXPECT_TRUE(decision.latched) << text;
    EXPECT_NE(decision.reason.find("corrupt"), std::string::npos) << decision.reason;
    EXPECT_NE(store_->Health().message.find("corrupt"), std::string::npos);
    EXPECT_TRUE(OnDisk().engaged) << "rewritten as a valid, latched file";
  }
  // The untouched valid file (clean stop, released) is accepted.
  WriteRaw(dir_ + "/estop_latch", valid);
  EXPECT_FALSE(Restart().latched);
}

TEST_F(EstopLatchStoreTest, AnUnwritableStateDirectoryLatchesAndIsReported) {
  // A path below a regular file can be neither read nor written, even by root.
  WriteRaw(dir_ + "/not_a_directory", "x");
  EstopLatchStore store(dir_ + "/not_a_directory");
  const EstopLatchDecision decision = store.Start();
  EXPECT_TRUE(decision.latched);
  EXPECT_NE(decision.reason.find("not_a_directory"), std::string::npos) << decision.reason;
  DeviceHealth health = store.Health();
  EXPECT_EQ(health.state, DeviceState::kError);
  EXPECT_NE(health.message.find("cannot persist the e-stop latch"), std::string::npos)
      << health.message;
  // A release cannot be recorded: refused to the caller, counted.
  std::string error;
  EXPECT_FALSE(store.Record(false, "", &error));
  EXPECT_FALSE(error.empty());
  health = store.Health();
  EXPECT_EQ(CounterOf(health, "write_failures"), 2u);
  EXPECT_EQ(CounterOf(health, "writes"), 0u);
  EXPECT_EQ(health.state, DeviceState::kError);

  // The state file is a directory: unreadable, and cannot be replaced.
  ASSERT_EQ(::mkdir((dir_ + "/estop_latch").c_str(), 0700), 0);
  EXPECT_TRUE(Restart().latched);
  EXPECT_EQ(store_->Health().state, DeviceState::kError);

  // A read-only directory (permissions do not bind root).
  if (::geteuid() != 0) {
    const std::string read_only = testing::MakeTempDir("mostar_estop_ro_");
    ASSERT_EQ(::chmod(read_only.c_str(), 0500), 0);
    EstopLatchStore ro(read_only);
    const EstopLatchDecision d = ro.Start();
    EXPECT_TRUE(d.latched);
    EXPECT_NE(d.reason.find("cannot record the latch"), std::string::npos) << d.reason;
    ::chmod(read_only.c_str(), 0700);
  }
}

TEST(EstopLatchFileTest, RoundTripsAndKeepsAHostileIdOnOneLine) {
  EstopLatchFile file{false, true, "alice"};
  EstopLatchFile back;
  std::string error;
  ASSERT_TRUE(ParseEstopLatchFile(FormatEstopLatchFile(file), &back, &error)) << error;
  EXPECT_FALSE(back.clean_stop);
  EXPECT_TRUE(back.engaged);
  EXPECT_EQ(back.engaged_by, "alice");
  // An id from the network cannot add lines (a forged "clean_stop 1") or grow the file.
  file.engaged_by = "x\nclean_stop 1\n" + std::string(1000, 'y');
  const std::string text = FormatEstopLatchFile(file);
  ASSERT_TRUE(ParseEstopLatchFile(text, &back, &error)) << error;
  EXPECT_FALSE(back.clean_stop);
  EXPECT_EQ(back.engaged_by.size(), 64u);
  EXPECT_EQ(back.engaged_by.find('\n'), std::string::npos);
  EXPECT_LT(text.size(), 200u);
}

}  // namespace
}  // namespace mostar::drive

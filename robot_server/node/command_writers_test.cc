#include "robot_server/node/command_writers.h"

#include <gtest/gtest.h>

namespace mostar::server {
namespace {

dds::WriterId Writer(uint8_t participant, uint8_t entity = 1) {
  dds::WriterId id;
  id.participant[0] = 0x80;
  id.participant[11] = participant;
  id.entity[3] = entity;
  return id;
}

TEST(CommandWriterTrackerTest, ALostWriterNamesItsClient) {
  CommandWriterTracker tracker;
  tracker.NoteCommand(Writer(1), "alice");
  tracker.NoteCommand(Writer(2), "bob");
  EXPECT_EQ(tracker.WriterLost(Writer(1)), "alice");
  EXPECT_EQ(tracker.WriterLost(Writer(1)), std::nullopt);  // already gone
  EXPECT_EQ(tracker.WriterLost(Writer(9)), std::nullopt);  // never wrote a command
  EXPECT_EQ(tracker.writers(), 1u);
}

// A restarted console: its new writer lives on while the old one's loss is reported.
TEST(CommandWriterTrackerTest, AClientWithAnotherLiveWriterIsNotLost) {
  CommandWriterTracker tracker;
  tracker.NoteCommand(Writer(1), "alice");
  tracker.NoteCommand(Writer(2), "alice");
  EXPECT_EQ(tracker.WriterLost(Writer(1)), std::nullopt);
  EXPECT_EQ(tracker.WriterLost(Writer(2)), "alice");
}

TEST(CommandWriterTrackerTest, AWriterSpeaksForItsLastClientAndTheTableIsBounded) {
  CommandWriterTracker tracker(/*max_writers=*/3);
  tracker.NoteCommand(Writer(1), "alice");
  tracker.NoteCommand(Writer(1), "bob");  // without DDS Security a writer may claim anyone
  for (uint8_t n = 10; n < 50; ++n) tracker.NoteCommand(Writer(n), "mallory");
  EXPECT_EQ(tracker.writers(), 3u);
  tracker.NoteCommand(Writer(1), "bob");
  EXPECT_EQ(tracker.WriterLost(Writer(1)), "bob");
}

}  // namespace
}  // namespace mostar::server

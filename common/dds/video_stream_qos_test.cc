// What the H.264 stream writer's QoS makes Fast DDS put on the wire: two real participants on
// loopback UDP (no shared memory, no intra-process shortcut) in one process, the writer's side
// through Fast DDS' test transport, which shows this test every HEARTBEAT it sends.
//
// Why it matters (docs/networking.md, "The robot_server restart"): with a heartbeat after every
// message, a reader that misses fragments asks for all of them again at the frame rate,
// including those already sent again and still on their way (Fast DDS 2.9 answers every
// NACK_FRAG at once), and on a long link one loss burst grows into a repair storm that fills
// the link for every other stream on it.
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/test_UDPv4TransportDescriptor.h>
#include <fastrtps/attributes/LibrarySettingsAttributes.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "common/dds/domain.h"
#include "common/dds/qos.h"
#include "mostar_msgsPubSubTypes.h"

namespace mostar::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
namespace frtps = eprosima::fastrtps;
using VideoType = mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType;

// Loopback UDP only; `transport` carries this participant's traffic. A fixed participant id:
// Fast DDS numbers participants on from the last one created in the process, and the initial
// peer only reaches the first five ids (its ports).
fdds::DomainParticipantQos LoopbackUdpQos(
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> transport,
    int32_t participant_id) {
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.wire_protocol().participant_id = participant_id;
  qos.transport().use_builtin_transports = false;
  qos.transport().user_transports.push_back(transport);
  frtps::rtps::Locator_t peer;
  peer.kind = LOCATOR_KIND_UDPv4;
  frtps::rtps::IPLocator::setIPv4(peer, "127.0.0.1");
  qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  return qos;
}

// The writer's participant counts the HEARTBEATs of user writers it sends (builtin discovery
// writers have entity kinds 0xc2/0xc3; a user writer's kind has the two top bits clear).
struct HeartbeatCountingSide {
  std::atomic<int> user_heartbeats{0};
  // Every DATA of a user writer with this RTPS sequence number (1 = the first write) is lost,
  // repairs included; 0: none.
  std::atomic<uint32_t> lost_sequence_number{0};
  std::shared_ptr<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor> Transport() {
    auto t = std::make_shared<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor>();
    t->interfaceWhiteList.push_back("127.0.0.1");
    // At the HEARTBEAT's body: readerId (4 octets), writerId (4, the kind last).
    t->drop_heartbeat_messages_filter_ = [this](frtps::rtps::CDRMessage_t& msg) {
      if (msg.pos + 8 <= msg.length && (msg.buffer[msg.pos + 7] & 0xc0) == 0) ++user_heartbeats;
      return false;  // never drop
    };
    // At the DATA's body: extraFlags, octetsToInlineQos (2 + 2), readerId (4), writerId (4, the
    // kind last), writerSN (high, low: 4 + 4, little endian on this machine's participants).
    t->drop_data_messages_filter_ = [this](frtps::rtps::CDRMessage_t& msg) {
      if (msg.pos + 20 > msg.length || (msg.buffer[msg.pos + 11] & 0xc0) != 0) return false;
      uint32_t low = 0;
      for (int i = 3; i >= 0; --i) low = (low << 8) | msg.buffer[msg.pos + 16 + i];
      return low == lost_sequence_number.load();
    };
    return t;
  }
};

class VideoStreamQosTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    // Two participants of one process would otherwise skip the network altogether.
    frtps::LibrarySettingsAttributes settings;
    settings.intraprocess_delivery = frtps::INTRAPROCESS_OFF;
    frtps::xmlparser::XMLProfileManager::library_settings(settings);
    const int domain = PerProcessDomainId();
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.push_back("127.0.0.1");
    writer_side_ = factory->create_participant(domain, LoopbackUdpQos(counting_.Transport(), 0));
    reader_side_ = factory->create_participant(domain, LoopbackUdpQos(udp, 1));
    ASSERT_NE(writer_side_, nullptr);
    ASSERT_NE(reader_side_, nullptr);
  }
  void TearDown() override {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    for (auto* p : {writer_side_, reader_side_}) {
      if (p == nullptr) continue;
      p->delete_contained_entities();
      factory->delete_participant(p);
    }
  }

  // A writer with `writer_qos` and a reader with the console's stream QoS on "rt/test/h264",
  // matched (or a test failure).
  std::pair<fdds::DataWriter*, fdds::DataReader*> MatchedPair(
      const fdds::DataWriterQos& writer_qos) {
    fdds::TypeSupport w_type(new VideoType()), r_type(new VideoType());
    w_type.register_type(writer_side_);
    r_type.register_type(reader_side_);
    auto* w_topic =
        writer_side_->create_topic("rt/test/h264", w_type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    auto* r_topic =
        reader_side_->create_topic("rt/test/h264", r_type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    auto* writer = writer_side_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT)
                       ->create_datawriter(w_topic, writer_qos);
    auto* reader = reader_side_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT)
                       ->create_datareader(r_topic, VideoStreamReaderQos(kVideoStreamDepth));
    EXPECT_NE(writer, nullptr);
    EXPECT_NE(reader, nullptr);
    if (writer == nullptr || reader == nullptr) return {writer, reader};
    // Both sides: a reader that has not matched the writer yet drops what it sends.
    fdds::PublicationMatchedStatus matched;
    fdds::SubscriptionMatchedStatus reader_matched;
    for (int i = 0; i < 500 && (matched.current_count == 0 || reader_matched.current_count == 0);
         ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      writer->get_publication_matched_status(matched);
      reader->get_subscription_matched_status(reader_matched);
    }
    EXPECT_EQ(matched.current_count, 1) << "no match within 5 s";
    EXPECT_EQ(reader_matched.current_count, 1) << "no match within 5 s";
    return {writer, reader};
  }

  // Writes `count` frames at 100 Hz with `writer_qos` to a matched reader with the console's
  // stream QoS; returns the user HEARTBEATs sent meanwhile and the frames received.
  std::pair<int, int> WriteFrames(const fdds::DataWriterQos& writer_qos, int count) {
    const auto [writer, reader] = MatchedPair(writer_qos);
    if (writer == nullptr || reader == nullptr) return {-1, -1};
    const int before = counting_.user_heartbeats.load();
    mostar_msgs::msg::dds_::StereoVideoFrame_ frame;
    frame.left().assign(2000, 0x42);
    frame.right().assign(2000, 0x24);
    int received = 0;
    fdds::SampleInfo info;
    mostar_msgs::msg::dds_::StereoVideoFrame_ taken;
    auto take = [&] {
      while (reader->take_next_sample(&taken, &info) == ReturnCode_t::RETCODE_OK) {
        if (info.valid_data) ++received;
      }
    };
    for (int i = 0; i < count; ++i) {
      frame.sequence_number(static_cast<uint64_t>(i));
      writer->write(&frame);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      take();
    }
    for (int i = 0; i < 100 && received < count; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      take();
    }
    return {counting_.user_heartbeats.load() - before, received};
  }

  // Writes `count` frames (AU numbers 0, 1, ...) every 20 ms with `writer_qos` to a matched
  // reader with the console's stream QoS, then takes for `listen` more; returns the AU numbers
  // taken, in order.
  std::vector<uint64_t> TakenAus(fdds::DataWriterQos writer_qos, int count,
                                 std::chrono::milliseconds listen,
                                 const std::function<void(fdds::DataWriter*)>& once_matched = {}) {
    // Each AU in a datagram of its own: the asynchronous sender puts AUs that queued up together
    // (a loaded machine) into one datagram, and the test transport then loses them all.
    writer_qos.publish_mode().kind = fdds::SYNCHRONOUS_PUBLISH_MODE;
    std::vector<uint64_t> taken_aus;
    const auto [writer, reader] = MatchedPair(writer_qos);
    if (writer == nullptr || reader == nullptr) return taken_aus;
    if (once_matched) once_matched(writer);
    mostar_msgs::msg::dds_::StereoVideoFrame_ frame;
    frame.left().assign(2000, 0x42);
    frame.right().assign(2000, 0x24);
    fdds::SampleInfo info;
    mostar_msgs::msg::dds_::StereoVideoFrame_ taken;
    auto take = [&] {
      while (reader->take_next_sample(&taken, &info) == ReturnCode_t::RETCODE_OK) {
        if (info.valid_data) taken_aus.push_back(taken.sequence_number());
      }
    };
    for (int i = 0; i < count; ++i) {
      frame.sequence_number(static_cast<uint64_t>(i));
      writer->write(&frame);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      take();
    }
    const auto end = std::chrono::steady_clock::now() + listen;
    while (std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      take();
    }
    return taken_aus;
  }

  HeartbeatCountingSide counting_;
  fdds::DomainParticipant* writer_side_ = nullptr;
  fdds::DomainParticipant* reader_side_ = nullptr;
};

// 60 frames in 0.6 s with a 5 s repair period: the history (depth 30) is full after the 30th
// write, yet no heartbeat follows the writes; the periodic one is 5 s away.
TEST_F(VideoStreamQosTest, TheStreamWriterSendsHeartbeatsOnlyAtItsRepairPeriod) {
  const auto [heartbeats, received] =
      WriteFrames(VideoStreamWriterQos(std::chrono::seconds(5), kVideoStreamDepth), 60);
  EXPECT_EQ(received, 60);
  EXPECT_LE(heartbeats, 2);
}

// The control: the same writes with the lanes' QoS (a heartbeat piggybacked on writes once the
// history is full) put a heartbeat on the wire for about every write past the 30th, which is
// what the test above would see if the stream writer piggybacked too.
TEST_F(VideoStreamQosTest, APiggybackingWriterSendsAHeartbeatWithEveryWriteOnceItsHistoryIsFull) {
  fdds::DataWriterQos piggybacking =
      VideoStreamWriterQos(std::chrono::seconds(5), kVideoStreamDepth);
  piggybacking.reliable_writer_qos().disable_heartbeat_piggyback = false;
  const auto [heartbeats, received] = WriteFrames(piggybacking, 60);
  EXPECT_EQ(received, 60);
  EXPECT_GE(heartbeats, 20);
}

// A NACK deadline: AU 4 never gets through (its repairs are lost too). With a 100 ms repair
// deadline it leaves the writer's history 100 ms after it was written, the reader gets a GAP
// and takes the AUs behind it; AU 4 is never taken, which the console sees as a jump in the
// AU numbers.
TEST_F(VideoStreamQosTest, PastTheRepairDeadlineTheReaderSkipsAnAuItCannotGetAndTakesTheRest) {
  counting_.lost_sequence_number = 5;  // RTPS numbers start at 1: AU 4
  const std::vector<uint64_t> taken =
      TakenAus(VideoStreamWriterQos(std::chrono::milliseconds(20), kVideoStreamDepth,
                                    std::chrono::milliseconds(100)),
               10, std::chrono::seconds(2));
  EXPECT_EQ(std::count(taken.begin(), taken.end(), 4u), 0);
  for (uint64_t au : {0u, 1u, 2u, 3u, 5u, 6u, 7u, 8u, 9u}) {
    EXPECT_EQ(std::count(taken.begin(), taken.end(), au), 1) << "AU " << au;
  }
  EXPECT_TRUE(std::is_sorted(taken.begin(), taken.end()));
}

// The control: without a deadline the writer keeps AU 4 (10 AUs are fewer than the history's
// 30) and repairs it every period; every repair is lost, so the reader holds everything behind
// it and takes only AUs 0-3.
TEST_F(VideoStreamQosTest, WithoutARepairDeadlineAnAuThatCannotBeRepairedHoldsEveryLaterOne) {
  counting_.lost_sequence_number = 5;
  const std::vector<uint64_t> taken =
      TakenAus(VideoStreamWriterQos(std::chrono::milliseconds(20), kVideoStreamDepth), 10,
               std::chrono::seconds(1));
  EXPECT_EQ(taken, (std::vector<uint64_t>{0, 1, 2, 3}));
}

// The robot follows its viewers' round trip with the deadline (RobotNode::SetVideoRepairDeadline):
// a writer created without one and given 100 ms once matched behaves as the one above.
TEST_F(VideoStreamQosTest, ARepairDeadlineSetWhileTheWriterRunsTakesEffect) {
  counting_.lost_sequence_number = 5;
  std::string error;
  bool set = false;
  const std::vector<uint64_t> taken =
      TakenAus(VideoStreamWriterQos(std::chrono::milliseconds(20), kVideoStreamDepth), 10,
               std::chrono::seconds(2), [&](fdds::DataWriter* writer) {
                 set = SetRepairDeadline(writer, std::chrono::milliseconds(100), &error);
                 EXPECT_EQ(writer->get_qos().lifespan().duration.nanosec, 100'000'000u);
               });
  ASSERT_TRUE(set) << error;
  EXPECT_EQ(std::count(taken.begin(), taken.end(), 4u), 0);
  for (uint64_t au : {0u, 1u, 2u, 3u, 5u, 6u, 7u, 8u, 9u}) {
    EXPECT_EQ(std::count(taken.begin(), taken.end(), au), 1) << "AU " << au;
  }
}

TEST(VideoStreamWriterQos, TheRepairDeadlineIsTheWritersLifespan) {
  EXPECT_EQ(VideoStreamWriterQos(std::chrono::milliseconds(50), 30).lifespan().duration,
            eprosima::fastrtps::c_TimeInfinite);
  const auto qos =
      VideoStreamWriterQos(std::chrono::milliseconds(50), 30, std::chrono::milliseconds(1250));
  EXPECT_EQ(qos.lifespan().duration.seconds, 1);
  EXPECT_EQ(qos.lifespan().duration.nanosec, 250'000'000u);
}

}  // namespace
}  // namespace mostar::dds

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

#include <atomic>
#include <chrono>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <memory>
#include <thread>

#include "common/dds/domain.h"
#include "common/dds/qos.h"
#include "mostar_msgsPubSubTypes.h"

namespace mostar::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
namespace frtps = eprosima::fastrtps;
using VideoType = mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType;

// Loopback UDP only; `transport` carries this participant's traffic.
fdds::DomainParticipantQos LoopbackUdpQos(
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> transport) {
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
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
  std::shared_ptr<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor> Transport() {
    auto t = std::make_shared<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor>();
    t->interfaceWhiteList.push_back("127.0.0.1");
    // At the HEARTBEAT's body: readerId (4 octets), writerId (4, the kind last).
    t->drop_heartbeat_messages_filter_ = [this](frtps::rtps::CDRMessage_t& msg) {
      if (msg.pos + 8 <= msg.length && (msg.buffer[msg.pos + 7] & 0xc0) == 0) ++user_heartbeats;
      return false;  // never drop
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
    writer_side_ = factory->create_participant(domain, LoopbackUdpQos(counting_.Transport()));
    reader_side_ = factory->create_participant(domain, LoopbackUdpQos(udp));
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

  // Writes `count` frames at 100 Hz with `writer_qos` to a matched reader with the console's
  // stream QoS; returns the user HEARTBEATs sent meanwhile and the frames received.
  std::pair<int, int> WriteFrames(const fdds::DataWriterQos& writer_qos, int count) {
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
    if (writer == nullptr || reader == nullptr) return {-1, -1};
    fdds::PublicationMatchedStatus matched;
    for (int i = 0; i < 500 && matched.current_count == 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      writer->get_publication_matched_status(matched);
    }
    EXPECT_EQ(matched.current_count, 1) << "no match within 5 s";
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

}  // namespace
}  // namespace mostar::dds

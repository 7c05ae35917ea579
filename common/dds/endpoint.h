// Typed DDS writer and reader over a mostar::dds::Participant.
//
//   Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType> w(participant, topics::kScan,
//                                                           Stream::kSensor);
//   Reader<...> r(participant, topics::kScan, Stream::kSensor,
//                 [](const LaserScan_& scan) { ... });   // called on a DDS thread
//   std::optional<LaserScan_> latest = r.Latest();         // or latest-value access
//   Reader<...> c(participant, topics::kCommand, Stream::kCommand, kWithWriter,
//                 [](const VelocityCommand_& c, const WriterId& from) { ... });
//
// `PubSubType` is a fastddsgen-generated `XxxPubSubType`; its `type` is the data class.
// Construction failures are reported by ok()/error(), never by exceptions. Destruction deletes
// the DDS entity; callbacks have stopped when the destructor returns.
#pragma once

#include <array>
#include <atomic>
#include <cstring>
#include <exception>
#include <fastdds/dds/core/status/LivelinessChangedStatus.hpp>
#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <functional>
#include <mutex>
#include <optional>
#include <string>

#include "common/dds/participant.h"
#include "common/dds/qos.h"
#include "common/dds/writer_id.h"

namespace mostar::dds {

// A fastddsgen type that refuses (returns false for) a sample it cannot decode. The generated
// deserialize catches only fastcdr's NotEnoughMemoryException: any other (BadParamException for
// an unknown encapsulation byte) went up through Fast DDS's take into the listener thread and
// ended the process, so one malformed sample from any writer on the topic stopped the robot.
// Writers use it too, since whichever endpoint registers a type name first in a participant
// decides the type its readers decode with. Fast DDS skips a refused sample.
template <class PubSubType>
class RefuseUndecodable : public PubSubType {
 public:
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return PubSubType::deserialize(payload, data);
    } catch (const std::exception&) {
      return false;
    }
  }
};

// The writer behind a SampleInfo::publication_handle or a LivelinessChangedStatus.
inline WriterId WriterIdFromHandle(const eprosima::fastrtps::rtps::InstanceHandle_t& handle) {
  const eprosima::fastrtps::rtps::GUID_t guid = eprosima::fastrtps::rtps::iHandle2GUID(handle);
  WriterId id;
  std::memcpy(id.participant.data(), guid.guidPrefix.value, id.participant.size());
  std::memcpy(id.entity.data(), guid.entityId.value, id.entity.size());
  return id;
}

// A change of the liveliness of the writers a reader matched (LIVELINESS_CHANGED).
struct LivelinessChange {
  WriterId writer;             // the writer whose liveliness changed
  int alive_count = 0;         // writers alive now
  int alive_count_change = 0;  // < 0: `writer` stopped being alive (lost or gone)
  int not_alive_count_change = 0;
};

// A change of the writers a reader matched (SUBSCRIPTION_MATCHED). Under DDS Security a match
// means access control accepted the writer: the permissions of the certificate its participant
// proved allow its topic and partitions.
struct MatchChange {
  WriterId writer;        // the writer matched (change > 0) or unmatched
  int current_count = 0;  // writers matched now
  int current_count_change = 0;
};

// " in partition 'P' (...)" when `qos` puts its endpoint in a partition (InPartition), for
// the error of an endpoint DDS refused: under DDS Security the permissions must allow it.
template <class Qos>
std::string PartitionNote(const Qos& qos) {
  for (const auto& property : qos.properties().properties()) {
    if (property.name() == "partitions") {
      return " in partition '" + property.value() +
             "' (with DDS Security, are the permissions signed for it? docs/security.md)";
    }
  }
  return "";
}

// Tag of the Reader constructor whose callback also gets the writer of each sample.
struct WithWriter {};
inline constexpr WithWriter kWithWriter{};

// Counts matched remote endpoints; shared by writers and readers.
class MatchCounter {
 public:
  int matched() const { return matched_.load(); }

 protected:
  std::atomic<int> matched_{0};
};

template <class PubSubType>
class Writer : public eprosima::fastdds::dds::DataWriterListener, public MatchCounter {
 public:
  using Data = typename PubSubType::type;

  // The int32_t that callers may still pass (the former command ownership strength) is
  // ignored: command ownership is shared (qos.h).
  Writer(Participant& participant, const std::string& topic_name, Stream stream,
         int32_t /*ignored*/ = 0)
      : Writer(participant, topic_name, WriterQos(stream)) {}
  // Called on a DDS thread when readers match (change > 0) or unmatch (change < 0).
  using MatchCallback = std::function<void(int current_count_change)>;
  // With QoS made by the caller (e.g. VideoWriterQos).
  Writer(Participant& participant, const std::string& topic_name,
         const eprosima::fastdds::dds::DataWriterQos& qos, MatchCallback on_match = {})
      : participant_(participant), on_match_(std::move(on_match)) {
    auto* topic = participant.GetTopic(
        topic_name, eprosima::fastdds::dds::TypeSupport(new RefuseUndecodable<PubSubType>()),
        &error_);
    if (topic == nullptr) return;
    writer_ = participant.publisher()->create_datawriter(
        topic, qos, this, eprosima::fastdds::dds::StatusMask::publication_matched());
    if (writer_ == nullptr) {
      error_ = "cannot create a DDS writer on " + topic_name + PartitionNote(qos);
    }
  }
  ~Writer() override {
    if (writer_ != nullptr) participant_.publisher()->delete_datawriter(writer_);
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  bool ok() const { return writer_ != nullptr; }
  const std::string& error() const { return error_; }

  // Publishes one sample; false when DDS refused it (counted in failures()).
  bool Write(const Data& data) {
    if (writer_ == nullptr) return false;
    Data copy = data;  // Fast DDS 2.9 takes a non-const pointer
    const bool ok = writer_->write(&copy);
    if (ok) {
      ++written_;
    } else {
      ++failures_;
    }
    return ok;
  }
  // True when every matched reliable reader acknowledged all samples (ack-clock pattern).
  bool AllAcknowledged() {
    return writer_ != nullptr && writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(
                                     0, 0)) == ReturnCode_t::RETCODE_OK;
  }
  uint64_t written() const { return written_.load(); }
  uint64_t failures() const { return failures_.load(); }
  eprosima::fastdds::dds::DataWriter* get() const { return writer_; }

  void on_publication_matched(
      eprosima::fastdds::dds::DataWriter*,
      const eprosima::fastdds::dds::PublicationMatchedStatus& info) override {
    matched_ = info.current_count;
    if (on_match_) on_match_(info.current_count_change);
  }

 private:
  Participant& participant_;
  MatchCallback on_match_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  std::string error_;
  std::atomic<uint64_t> written_{0};
  std::atomic<uint64_t> failures_{0};
};

template <class PubSubType>
class Reader : public eprosima::fastdds::dds::DataReaderListener, public MatchCounter {
 public:
  using Data = typename PubSubType::type;
  using Callback = std::function<void(const Data&)>;
  using WriterCallback = std::function<void(const Data&, const WriterId&)>;
  // Called when the liveliness of a matched writer changes (command stream).
  using LivelinessCallback = std::function<void(const LivelinessChange&)>;
  // Called when a writer matches or unmatches.
  using MatchCallback = std::function<void(const MatchChange&)>;

  Reader(Participant& participant, const std::string& topic_name, Stream stream,
         Callback callback = {}, LivelinessCallback on_liveliness = {})
      : Reader(participant, topic_name, stream, kWithWriter,
               callback ? WriterCallback([callback = std::move(callback)](
                                             const Data& data, const WriterId&) { callback(data); })
                        : WriterCallback(),
               std::move(on_liveliness)) {}

  // `callback` also gets the writer of each sample (SampleInfo::publication_handle).
  Reader(Participant& participant, const std::string& topic_name, Stream stream, WithWriter,
         WriterCallback callback, LivelinessCallback on_liveliness = {})
      : Reader(participant, topic_name, ReaderQos(stream), kWithWriter, std::move(callback),
               std::move(on_liveliness)) {}
  // With QoS made by the caller (e.g. InPartition(ReaderQos(stream), partition)).
  Reader(Participant& participant, const std::string& topic_name,
         const eprosima::fastdds::dds::DataReaderQos& qos, WithWriter, WriterCallback callback,
         LivelinessCallback on_liveliness = {}, MatchCallback on_match = {})
      : participant_(participant),
        callback_(std::move(callback)),
        on_liveliness_(std::move(on_liveliness)),
        on_match_(std::move(on_match)) {
    auto* topic = participant.GetTopic(
        topic_name, eprosima::fastdds::dds::TypeSupport(new RefuseUndecodable<PubSubType>()),
        &error_);
    if (topic == nullptr) return;
    using eprosima::fastdds::dds::StatusMask;
    reader_ = participant.subscriber()->create_datareader(topic, qos, this,
                                                          StatusMask::data_available()
                                                              << StatusMask::subscription_matched()
                                                              << StatusMask::liveliness_changed());
    if (reader_ == nullptr) {
      error_ = "cannot create a DDS reader on " + topic_name + PartitionNote(qos);
    }
  }
  ~Reader() override {
    if (reader_ != nullptr) {
      reader_->set_listener(nullptr);
      participant_.subscriber()->delete_datareader(reader_);
    }
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  bool ok() const { return reader_ != nullptr; }
  const std::string& error() const { return error_; }

  // The most recent sample received, if any.
  std::optional<Data> Latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
  }
  uint64_t received() const { return received_.load(); }

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    Data data;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      ++received_;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        latest_ = data;
      }
      if (callback_) callback_(data, WriterIdFromHandle(info.publication_handle));
    }
  }
  void on_subscription_matched(
      eprosima::fastdds::dds::DataReader*,
      const eprosima::fastdds::dds::SubscriptionMatchedStatus& info) override {
    matched_ = info.current_count;
    if (!on_match_) return;
    MatchChange change;
    change.writer = WriterIdFromHandle(info.last_publication_handle);
    change.current_count = info.current_count;
    change.current_count_change = info.current_count_change;
    on_match_(change);
  }
  void on_liveliness_changed(eprosima::fastdds::dds::DataReader*,
                             const eprosima::fastdds::dds::LivelinessChangedStatus& s) override {
    if (!on_liveliness_) return;
    LivelinessChange change;
    change.writer = WriterIdFromHandle(s.last_publication_handle);
    change.alive_count = s.alive_count;
    change.alive_count_change = s.alive_count_change;
    change.not_alive_count_change = s.not_alive_count_change;
    on_liveliness_(change);
  }

 private:
  Participant& participant_;
  WriterCallback callback_;
  LivelinessCallback on_liveliness_;
  MatchCallback on_match_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  std::string error_;
  mutable std::mutex mutex_;
  std::optional<Data> latest_;
  std::atomic<uint64_t> received_{0};
};

}  // namespace mostar::dds

#include "common/dds/qos.h"

#include <algorithm>

namespace mostar::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::Duration_t;

const char* StreamName(Stream stream) {
  switch (stream) {
    case Stream::kVideo:
      return "video";
    case Stream::kSensor:
      return "sensor";
    case Stream::kCommand:
      return "command";
    case Stream::kState:
      return "state";
    case Stream::kControl:
      return "control";
  }
  return "?";
}

namespace {

struct Common {
  fdds::ReliabilityQosPolicyKind reliability;
  int32_t depth;
  fdds::DurabilityQosPolicyKind durability;
};

Common CommonOf(Stream stream) {
  switch (stream) {
    case Stream::kVideo:
      return {fdds::RELIABLE_RELIABILITY_QOS, 1, fdds::VOLATILE_DURABILITY_QOS};
    case Stream::kSensor:
      return {fdds::BEST_EFFORT_RELIABILITY_QOS, kSensorDepth, fdds::VOLATILE_DURABILITY_QOS};
    case Stream::kCommand:
      return {fdds::RELIABLE_RELIABILITY_QOS, 1, fdds::VOLATILE_DURABILITY_QOS};
    case Stream::kState:
      return {fdds::RELIABLE_RELIABILITY_QOS, 1, fdds::TRANSIENT_LOCAL_DURABILITY_QOS};
    case Stream::kControl:
      return {fdds::RELIABLE_RELIABILITY_QOS, 10, fdds::VOLATILE_DURABILITY_QOS};
  }
  return {fdds::BEST_EFFORT_RELIABILITY_QOS, 1, fdds::VOLATILE_DURABILITY_QOS};
}

}  // namespace

fdds::DataWriterQos WriterQos(Stream stream) {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  const Common c = CommonOf(stream);
  qos.reliability().kind = c.reliability;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = c.depth;
  qos.durability().kind = c.durability;
  // Unbounded generated types: keep the realloc memory mode (see fastdds notes).
  qos.endpoint().history_memory_policy =
      eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  if (c.reliability == fdds::RELIABLE_RELIABILITY_QOS) {
    qos.reliable_writer_qos().times.heartbeatPeriod = Duration_t(0, 50'000'000);
  }
  if (stream == Stream::kVideo) {
    // Periodic heartbeats only: one per write would make every reader that misses fragments of
    // an earlier pair ask for them again at the frame rate.
    qos.reliable_writer_qos().disable_heartbeat_piggyback = true;
  }
  // Writers never block the caller: a full transport (TCP on a slow link) must not freeze a
  // capture, control or UI thread. Samples are handed to Fast DDS's sending thread; with
  // keep-last 1 a newer sample replaces one not yet sent.
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  if (stream == Stream::kCommand) {
    qos.ownership().kind = fdds::SHARED_OWNERSHIP_QOS;
    qos.deadline().period = Duration_t(kCommandDeadlineSeconds);
    qos.liveliness().kind = fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
    qos.liveliness().lease_duration = Duration_t(kCommandLivelinessSeconds);
    qos.liveliness().announcement_period = Duration_t(kCommandLivelinessSeconds / 3);
  }
  return qos;
}

fdds::DataWriterQos VideoWriterQos(std::chrono::milliseconds repair_period) {
  fdds::DataWriterQos qos = WriterQos(Stream::kVideo);
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(repair_period).count();
  qos.reliable_writer_qos().times.heartbeatPeriod = Duration_t(
      static_cast<int32_t>(ns / 1'000'000'000), static_cast<uint32_t>(ns % 1'000'000'000));
  // Keep-last 1: the history is full after every write, so Fast DDS 2.9 piggybacks a heartbeat
  // on each one (StatefulWriter::send_heartbeat_piggyback_nts_).
  qos.reliable_writer_qos().disable_heartbeat_piggyback = false;
  return qos;
}

fdds::DataWriterQos VideoStreamWriterQos(std::chrono::milliseconds repair_period, int32_t depth,
                                         std::chrono::milliseconds repair_deadline) {
  fdds::DataWriterQos qos = VideoWriterQos(repair_period);
  qos.history().depth = std::max<int32_t>(1, depth);
  if (repair_deadline > std::chrono::milliseconds::zero()) {
    // Fast DDS 2.9 removes expired samples from the writer's history on a timer (their source
    // timestamp + lifespan: the writer's clock only); each reader proxy then gets a GAP for them.
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(repair_deadline).count();
    qos.lifespan().duration = Duration_t(static_cast<int32_t>(ns / 1'000'000'000),
                                         static_cast<uint32_t>(ns % 1'000'000'000));
  }
  // Periodic heartbeats only. Once `depth` access units are held the history is full after
  // every write, and Fast DDS 2.9 would piggyback a heartbeat on every message it sends, repairs
  // included; each one makes a reader ask again for every fragment it still misses, also those
  // already sent again and on their way (NACK_FRAG has no suppression), so one loss burst on a
  // full link multiplies into a repair storm that starves everything else on that link.
  // (No nackSupressionDuration: Fast DDS 2.9 restarts its one timer per reader at every send, so
  // with a write every 33 ms a period of about the round trip would never expire and no NACK
  // would be answered while the stream flows.)
  qos.reliable_writer_qos().disable_heartbeat_piggyback = true;
  return qos;
}

bool SetRepairDeadline(fdds::DataWriter* writer, std::chrono::milliseconds repair_deadline,
                       std::string* error) {
  if (writer == nullptr) {
    *error = "no writer";
    return false;
  }
  fdds::DataWriterQos qos = writer->get_qos();
  if (repair_deadline > std::chrono::milliseconds::zero()) {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(repair_deadline).count();
    qos.lifespan().duration = Duration_t(static_cast<int32_t>(ns / 1'000'000'000),
                                         static_cast<uint32_t>(ns % 1'000'000'000));
  } else {
    qos.lifespan().duration = eprosima::fastrtps::c_TimeInfinite;
  }
  const eprosima::fastrtps::types::ReturnCode_t rc = writer->set_qos(qos);
  if (rc != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
    *error = "set_qos(lifespan) returned " + std::to_string(rc());
    return false;
  }
  return true;
}

fdds::DataReaderQos VideoStreamReaderQos(int32_t depth) {
  fdds::DataReaderQos qos = ReaderQos(Stream::kVideo);
  depth = std::max<int32_t>(1, depth);
  qos.history().depth = depth;
  qos.resource_limits().max_samples_per_instance = depth + kMissingSampleAllowance;
  qos.resource_limits().max_samples = depth + kMissingSampleAllowance;
  qos.resource_limits().allocated_samples = 1;
  return qos;
}

fdds::DataReaderQos ReaderQos(Stream stream) {
  fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
  const Common c = CommonOf(stream);
  qos.reliability().kind = c.reliability;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  const int32_t depth = stream == Stream::kCommand ? kCommandReaderDepth : c.depth;
  qos.history().depth = depth;
  qos.durability().kind = c.durability;
  // Bounded: keyless topics have one instance; keep-last holds at most `depth` samples of it.
  // The sample limit leaves room for kMissingSampleAllowance samples announced but not yet
  // received (a reliable reader refuses a sample while history + missing reach the limit).
  qos.resource_limits().max_instances = 1;
  qos.resource_limits().max_samples_per_instance = depth + kMissingSampleAllowance;
  qos.resource_limits().max_samples = depth + kMissingSampleAllowance;
  qos.resource_limits().allocated_samples = depth;
  // Bounded types (commands, e-stop, control requests, clock probes): samples of the type's
  // maximum size, preallocated; a bigger one is refused by the RTPS reader. Other types
  // (images, scans) grow as needed.
  qos.endpoint().history_memory_policy =
      stream == Stream::kCommand || stream == Stream::kControl
          ? eprosima::fastrtps::rtps::PREALLOCATED_MEMORY_MODE
          : eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  if (stream == Stream::kCommand) {
    qos.ownership().kind = fdds::SHARED_OWNERSHIP_QOS;
    qos.deadline().period = Duration_t(kCommandDeadlineSeconds);
    qos.liveliness().kind = fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
    qos.liveliness().lease_duration = Duration_t(kCommandLivelinessSeconds);
  }
  return qos;
}

namespace {

template <class Qos>
Qos WithPartitionProperty(Qos qos, const std::string& partition) {
  auto& properties = qos.properties().properties();
  for (auto it = properties.begin(); it != properties.end();) {
    it = it->name() == "partitions" ? properties.erase(it) : it + 1;
  }
  properties.emplace_back("partitions", partition);
  return qos;
}

}  // namespace

fdds::DataWriterQos InPartition(fdds::DataWriterQos qos, const std::string& partition) {
  return WithPartitionProperty(std::move(qos), partition);
}
fdds::DataReaderQos InPartition(fdds::DataReaderQos qos, const std::string& partition) {
  return WithPartitionProperty(std::move(qos), partition);
}

}  // namespace mostar::dds
